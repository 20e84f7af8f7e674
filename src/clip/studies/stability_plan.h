// stability's plan, as the CLI and the Python module both make it: the options, the defaults
// (the scene's value x 1..10000, T <= 0.2 s, steps from the stiffest estimate / 32 to T / 50),
// the swept scenes, the memory check and the lanes. tools/cli/studies/cmd_stability.cpp parses
// and prints; this decides what runs. Every function throws UsageError naming the option.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "clip/common/scene_options.h"
#include "clip/studies/study_common.h"
#include "core/model/model.h"
#include "scene/scene_def.h"
#include "study/parameter_sweep.h"
#include "study/stability.h"

namespace clothsim::clip {

struct StabilityOptions {
  SceneOptions scene;
  std::string integrators = default_comparison_list();  // compare's default four, by name
  std::string param = "cloth.springs.structural.stiffness";
  std::optional<std::string> values;  // not given: the scene's value x kDefaultValueFactors
  std::optional<double> min_dt, max_dt;
  double precision = analysis::StabilitySpec{}.precision;
  double energy_factor = analysis::StabilitySpec{}.energy_factor;
  double max_strain = analysis::StabilitySpec{}.max_strain;
  std::string frame_dts = kDefaultFrameDts;  // implicit_euler only; "none" for none
  std::string csv, plot, summary;
  std::string shard;  // --shard K/N|auto (study_shard.h)
  int jobs = 0;
};

inline constexpr double kDefaultValueFactors[] = {1.0, 10.0, 100.0, 1000.0, 10000.0};
inline constexpr double kStabilityDefaultDuration = 0.2;  // s
inline constexpr double kMaxDtOverSceneDt = 1000;  // the largest step tried, in scene steps,
inline constexpr double kMinStepsAtMaxDt = 50;     // and in steps per run
inline constexpr double kMinDtDivisor = 32;        // the smallest step tried: estimate / this

// Lane spellings (Lane::stepless_spelling), by StabilityLimit::lane: the CSV's and summary's names.
using LaneNames = std::vector<std::string>;

// One swept value's model (every lane searches on it, with its own settings: refs()).
struct StabilityCaseModels {
  double value;
  Model model;
};

// The whole study, planned: the lanes, the values and their models, the search's bounds.
struct StabilityStudy {
  std::vector<Lane> lanes;
  LaneNames names;                          // per lane
  std::vector<double> values;               // per case
  std::vector<StabilityCaseModels> cases;   // per value, models built
  analysis::StabilitySpec spec;
  // The cases as stability_sweep takes them, pointing into `cases` (each lane's settings on
  // its model: clip::lane_settings): call it once the study stays where it is.
  std::vector<analysis::StabilityCase> refs() const;
};

// As `clothsim stability` plans it: lanes, swept values (--values or the scene's x
// kDefaultValueFactors), T (--duration or min(scene, kStabilityDefaultDuration)), the memory
// check, every case's model, the steps tried. Outputs are the caller's to check.
StabilityStudy plan_stability(const StabilityOptions& o, const SceneDef& base);

// The swept scenes: --values, or the scene's value of --param times kDefaultValueFactors.
std::vector<analysis::SweepScene> sweep_cases(const StabilityOptions& o, const SceneDef& base,
                                              std::vector<double>& values);

// Every case's Model (they are all built up front), and a run on each thread at once.
void check_stability_memory(const StabilityOptions& o, const SceneDef& base, const std::vector<analysis::SweepScene>& scenes,
                            const std::vector<IntegratorKind>& kinds);

// The search's bounds and rules: --min-dt/--max-dt (or from the scene and the stiffest case), the rest as given.
void finish_stability_spec(const StabilityOptions& o, const SceneDef& base, double smallest_estimate,
                           analysis::StabilitySpec& spec);

// The study's lanes, as the scene runs them (a fixed-point scene's implicit_euler named so).
std::vector<Lane> stability_lanes(const StabilityOptions& o, const SceneDef& base);

}  // namespace clothsim::clip
