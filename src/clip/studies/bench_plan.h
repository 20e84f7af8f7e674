// bench's plan, as the CLI and the Python module both make it: the options, the defaults
// (six steps around the scene's dt, a T the reference can afford), the memory check, and the
// --vary studies. tools/cli/studies/cmd_bench.cpp parses and prints; this decides what runs.
// Every function throws UsageError with a one-line message naming the option.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "clip/common/scene_options.h"
#include "clip/studies/study_common.h"
#include "scene/scene_def.h"
#include "study/scale_study.h"
#include "study/work_precision.h"

namespace clothsim::clip {

using analysis::WorkPrecisionResult;
using analysis::WorkPrecisionSpec;

struct BenchOptions {
  SceneOptions scene;
  std::string integrators = default_comparison_list();  // compare's default four, by name
  std::optional<std::string> dts;  // not given: derived from the scene's dt
  std::optional<std::string> tols;  // the adaptive lanes' tolerances; not given: kDefaultTolerances
  std::string frame_dts = kDefaultFrameDts;  // implicit_euler only; "none" for none
  std::string csv, plot, summary;
  std::string shard;  // --shard K/N|auto (study_shard.h)
  std::string vary;   // --vary KEY=V1,V2,...: the study once per value (plan_values)
  std::string scale;  // --scale N1,N2,...: cost against sheet size (study/scale_study.h)
  std::string budget; // --budget N: substeps x iterations at equal cost (budget_plan.h)
  int jobs = 0;
  std::string error = "time";  // --error time|end: the largest over the sample times, or at T
  int reference_refinement = WorkPrecisionSpec{}.reference_refinement;
  double reference_tolerance = WorkPrecisionSpec{}.reference_tolerance;
  bool no_reference_cache = false;  // --no-reference-cache: computed, never stored
};

inline constexpr double kDefaultStepFactors[] = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
// An adaptive lane's tolerances when --tols is not given: six decades, as the steps are six
// doublings, from where the drapes' pairs first stay stable to well below the eye.
inline constexpr double kDefaultTolerances[] = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
inline constexpr double kMaxDefaultDuration = 0.5;    // s
inline constexpr double kMaxDefaultSmallSteps = 8000;  // T <= this x the smallest step

// Lane spellings (Lane::stepless_spelling), by point.lane: the CSV's and summary's names.
using LaneNames = std::vector<std::string>;

// The study's lanes, as the scene runs them (a fixed-point scene's implicit_euler named so); an
// @STEP refused (bench sweeps the steps), and an adaptive lane's :tol= (bench sweeps --tols).
std::vector<Lane> bench_lanes(const BenchOptions& o, const SceneDef& scene);

// T when --duration is not given: short enough for the reference, a multiple of every step.
double default_duration(double scene_duration, const std::vector<double>& dts);

// The study to run: steps (--dts or the scene's x kDefaultStepFactors), T, the frame steps.
WorkPrecisionSpec plan_bench(const BenchOptions& o, const SceneDef& scene, const std::vector<Lane>& lanes);

// One Model, and a run on each of the pool's threads at once (the dearest integrator's).
void check_bench_memory(const BenchOptions& o, const SceneDef& scene, const std::vector<IntegratorKind>& kinds);

// The study's model: `scene` run to T at least (its duration is informational only), the runs'
// memory checked against --max-memory, built.
Model build_bench_model(const BenchOptions& o, SceneDef& scene, const std::vector<Lane>& lanes,
                        const WorkPrecisionSpec& spec);

// Each lane's settings on `model` into spec.lane_settings (clip::lane_settings): every lane
// runs on `model` itself.
void attach_lane_settings(const Model& model, const std::vector<Lane>& lanes, WorkPrecisionSpec& spec);

// A study ready to run: the scene's model (build_bench_model) and the spec with each lane's
// settings (attach_lane_settings). Not copied: a Model is large.
struct BenchModels {
  BenchModels(const BenchOptions& o, SceneDef& scene, const std::vector<Lane>& lanes, WorkPrecisionSpec plan);
  BenchModels(const BenchModels&) = delete;
  BenchModels& operator=(const BenchModels&) = delete;
  const Model model;
  WorkPrecisionSpec spec;
};

// --vary KEY=V1,V2,...: the study once per value, each on its own scene (the user's --set, then
// the key's) against its own reference, its lanes labelled "rk4 (ks = 2e4)" in the table, the
// CSV's integrator column and the plot's legend. Spelt as compare spells it: in both the values
// make lanes, where stability's --param KEY makes the axis of its plot.
struct ValueStudy {
  std::string label;  // "ks = 2e4"
  SceneDef scene;
  LaneNames names;    // per lane
  WorkPrecisionSpec spec;
  WorkPrecisionResult result;
};

std::vector<ValueStudy> plan_values(const BenchOptions& o, const SceneDef& base, const std::vector<Lane>& lanes);

// --scale N1,N2,...: each lane (NAME@STEP, the scene's dt without) at each side N, the sheet's
// size and total mass fixed, to T = --duration (default min(scene, kMaxScaleDuration)); no
// reference. Every size's scene read and its memory checked before any run.
inline constexpr double kMaxScaleDuration = 0.2;  // s
struct ScalePlan {
  std::vector<int> sides;
  std::shared_ptr<const std::vector<Lane>> lanes;  // shared with spec.lane_settings
  analysis::ScaleSpec spec;
};
ScalePlan plan_scale(const BenchOptions& o);
// Every size's runs held to --max-memory, before any run.
void check_scale_memory(const BenchOptions& o, const ScalePlan& plan);

}  // namespace clothsim::clip
