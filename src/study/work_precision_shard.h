// A bench shard (shard.h): the reference first, then its points, each measured against the
// reference as it finishes so it can be journaled at once (the single-process study runs
// everything in one pool and measures at the end). Every shard runs the reference: it is
// what every error is measured against, and shipping it between array tasks would need a
// task of its own that all others wait for. Its positions are saved (reference_text), so a
// requeued shard does not run it again.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "work_precision.h"

namespace clothsim::analysis {

struct ShardReference {
  bool stopped = false;   // the caller stopped it: nothing to save
  bool finished = false;  // both runs reached T
  bool fine_finished = false;  // the finer one did: errors are measured against it
  double dt = 0.0;        // s, the finer step
  double change_rms = 0.0, change_max = 0.0;  // m, between the two runs (when finished)
  State fine;             // its final x and inv_mass, what errors are measured against
};

// Both reference runs at once (on up to two of spec.jobs threads).
ShardReference run_reference(const Model& model, const WorkPrecisionSpec& spec, const StudyHooks& hooks);

// The reference as text (every number exact, hex floats) and back; read_reference throws
// StudyError when the text is not one.
std::string reference_text(const ShardReference& ref, int particles);
ShardReference read_reference(const std::string& text);

// The points `items` (indices into planned_points(spec)) against `ref`; `finished` is told of
// each as it completes (calls serialised). Points the caller stopped are left out.
std::vector<WorkPrecisionPoint> run_points(const Model& model, const WorkPrecisionSpec& spec,
                                           const ShardReference& ref, const std::vector<std::size_t>& items,
                                           const StudyHooks& hooks,
                                           const std::function<void(std::size_t, const WorkPrecisionPoint&)>& finished);

}  // namespace clothsim::analysis
