// The study in two phases, as a single process and a bench shard (shard.h) both run it: the
// reference first (both of its runs at once), its positions kept at every sample time
// (sample_times), then the points, each measured against it at those times as it runs and
// reported as it finishes, so a shard journals it at once. Every shard runs the reference: it
// is what every error is measured against, and shipping it between array tasks would need a
// task of its own that all others wait for. Its positions are saved (reference_text), so a
// requeued shard does not run it again.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "work_precision.h"

namespace clothsim::analysis {

// The finer reference run's cloth at one sample time: what errors there are measured against.
struct ReferenceSample {
  Eigen::Matrix3Xd x;     // (3 x P) m
  Eigen::VectorXd free;   // (P) inverse masses there: a particle pinned then has no error
};

struct ShardReference {
  bool stopped = false;   // the caller stopped it: nothing to save
  bool finished = false;  // both runs reached T
  bool fine_finished = false;  // the finer one did: errors are measured against it
  bool coarse_finished = false;
  double dt = 0.0;        // s, the finer step
  // m, between the two runs (when finished): at T, and the largest over the sample times
  // (each the RMS or largest particle distance at one time).
  double change_rms = 0.0, change_max = 0.0;
  double change_rms_over_time = 0.0, change_max_over_time = 0.0;
  State fine;             // its final x and inv_mass, what errors at T are measured against
  std::vector<ReferenceSample> samples;  // at sample_times(spec)[k], as far as the finer run got
  // Not saved (reference_text): what a single-process study reports of the reference.
  RunTotals coarse_totals, fine_totals;
  std::optional<Divergence> coarse_divergence, fine_divergence;
  // The finer run's cloth within two contact margins of a collider at T: taken from its whole
  // state (fine keeps the cloth's columns only), and kept with a cached reference.
  bool touches_at_end = false;
};

// Both reference runs at once (on up to two of spec.jobs threads).
ShardReference run_reference(const Model& model, const WorkPrecisionSpec& spec, const StudyHooks& hooks);

// The reference as text (every number exact, hex floats), its samples included, and back;
// read_reference throws StudyError when the text is not one.
std::string reference_text(const ShardReference& ref, int particles);
ShardReference read_reference(const std::string& text);

// The points `items` (indices into planned_points(spec)) against `ref`; `finished` is told of
// each as it completes (calls serialised). Points the caller stopped are left out.
std::vector<WorkPrecisionPoint> run_points(const Model& model, const WorkPrecisionSpec& spec,
                                           const ShardReference& ref, const std::vector<std::size_t>& items,
                                           const StudyHooks& hooks,
                                           const std::function<void(std::size_t, const WorkPrecisionPoint&)>& finished);

}  // namespace clothsim::analysis
