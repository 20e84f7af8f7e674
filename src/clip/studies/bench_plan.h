// bench's plan, as the CLI and the Python module both make it: the options, the defaults
// (six steps around the scene's dt, a T the reference can afford), the memory check, and the
// --vary studies. tools/cli/studies/cmd_bench.cpp parses and prints; this decides what runs.
// Every function throws UsageError with a one-line message naming the option.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "clip/common/scene_options.h"
#include "clip/studies/study_common.h"
#include "scene/scene_def.h"
#include "study/work_precision.h"

namespace clothsim::cli {

using analysis::WorkPrecisionResult;
using analysis::WorkPrecisionSpec;

struct BenchOptions {
  SceneOptions scene;
  std::string integrators = default_comparison_list();  // the course's four, by name
  std::optional<std::string> dts;  // not given: derived from the scene's dt
  std::string frame_dts = kDefaultFrameDts;  // implicit_euler only; "none" for none
  std::string csv, plot, summary;
  std::string shard;  // --shard K/N|auto (study_shard.h)
  std::string vary;   // --vary KEY=V1,V2,...: the study once per value
  std::string scale;  // --scale N1,N2,...: cost against sheet size (study/scale_study.h)
  int jobs = 0;
  int reference_refinement = WorkPrecisionSpec{}.reference_refinement;
  double reference_tolerance = WorkPrecisionSpec{}.reference_tolerance;
};

inline constexpr double kDefaultStepFactors[] = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0};
inline constexpr double kMaxDefaultDuration = 0.5;    // s
inline constexpr double kMaxDefaultSmallSteps = 8000;  // T <= this x the smallest step

// Lane spellings (LaneSpec::stepless_spelling), by point.lane: the CSV's and summary's names.
using LaneNames = std::vector<std::string>;

// T when --duration is not given: short enough for the reference, a multiple of every step.
double default_duration(double scene_duration, const std::vector<double>& dts);

// The study to run: steps (--dts or the scene's x kDefaultStepFactors), T, the frame steps.
WorkPrecisionSpec plan_bench(const BenchOptions& o, const SceneDef& scene, const std::vector<LaneSpec>& lanes);

// One Model, and a run on each of the pool's threads at once (the dearest integrator's).
void check_bench_memory(const BenchOptions& o, const SceneDef& scene, const std::vector<IntegratorKind>& kinds);

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

std::vector<ValueStudy> plan_values(const BenchOptions& o, const SceneDef& base, const std::vector<LaneSpec>& lanes);

}  // namespace clothsim::cli
