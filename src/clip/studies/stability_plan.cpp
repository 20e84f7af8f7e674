#include "stability_plan.h"

#include <algorithm>
#include <cmath>

#include "clip/common/cli_common.h"
#include "clip/common/memory_budget.h"
#include "core/model/stiffness_estimate.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/param_keys.h"
#include "scene/scene_parser.h"
#include "study/task_pool.h"

namespace clothsim::clip {

// The swept scenes: --values, or the scene's value of --param times kDefaultValueFactors.
std::vector<analysis::SweepScene> sweep_cases(const StabilityOptions& o, const SceneDef& base,
                                              std::vector<double>& values) {
  ParamKey key;  // a path, a glob or an alias (ks, kd): scene/param_keys.h
  try {
    key = resolve_param_key(o.param, base);
  } catch (const ParamKeyError& e) {
    throw UsageError("--param " + std::string(e.what()));
  }
  if (!o.values) {
    const std::optional<double> current = analysis::parameter_value(o.scene.path, o.scene.sets, key.paths.front());
    if (!current) {
      // A key the scene has no number for may be no key at all (a typo): the parser says so,
      // with the nearest key, of --param as typed.
      std::vector<std::string> sets = o.scene.sets;
      for (const std::string& set : param_sets(key, 1.0)) sets.push_back(set);
      try {
        (void)load_scene(o.scene.path, sets);
      } catch (const SceneError& e) {
        throw as_option_error(e, key, "--param " + o.param);
      }
      throw UsageError("--values: " + base.source + " gives " + o.param +
                       " no number to scale the default values from; list the values");
    }
    for (double f : kDefaultValueFactors) values.push_back(f * *current);
  } else {
    values = parse_number_list(*o.values, "--values");
  }
  try {
    return analysis::sweep_scenes(o.scene.path, o.scene.sets, key.paths, values);
  } catch (const analysis::StudyError& e) {
    throw UsageError("--param " + std::string(e.what()));
  } catch (const SceneError& e) {  // said of --param as typed, not of the --set it became
    throw as_option_error(e, key, "--param " + o.param);
  }
}

// Every case's Model (they are all built up front), and a run on each thread at once.
void check_stability_memory(const StabilityOptions& o, const SceneDef& base, const std::vector<analysis::SweepScene>& scenes,
                            const std::vector<IntegratorKind>& kinds) {
  MemoryBudget budget;
  double models = 0.0, dearest = 0.0;
  for (const analysis::SweepScene& s : scenes) {
    models += model_bytes(s.scene);
    for (IntegratorKind k : kinds) dearest = std::max(dearest, run_bytes(s.scene, k));
  }
  budget.add(std::to_string(scenes.size()) + " models", models);
  const int threads = analysis::resolve_jobs(o.jobs);
  budget.add(std::to_string(threads) + " runs at once", threads * dearest);
  budget.check(base.source, o.scene.max_memory);
}

// The search's bounds and rules: --min-dt/--max-dt (or from the scene and the stiffest case), the rest as given.
void finish_stability_spec(const StabilityOptions& o, const SceneDef& base, double smallest_estimate,
                           analysis::StabilitySpec& spec) {
  spec.max_dt = o.max_dt ? *o.max_dt : std::min(spec.duration / kMinStepsAtMaxDt, kMaxDtOverSceneDt * base.dt);
  spec.min_dt = o.min_dt ? *o.min_dt : std::min(base.dt, smallest_estimate) / kMinDtDivisor;
  spec.precision = o.precision;
  spec.energy_factor = o.energy_factor;
  spec.max_strain = o.max_strain;
  spec.jobs = o.jobs;
  spec.frame_dts = parse_frame_dts(o.frame_dts);
  if (o.jobs < 0) throw UsageError("--jobs: must be >= 0 (0: one per core)");
  if (o.min_dt && !(*o.min_dt > 0.0)) throw UsageError("--min-dt: must be > 0 s");
  if (o.max_dt && !(*o.max_dt > 0.0)) throw UsageError("--max-dt: must be > 0 s");
  try {
    analysis::check(spec);
  } catch (const analysis::StudyError& e) {
    throw UsageError(std::string("stability: ") + e.what() + " (--min-dt, --max-dt, --duration, --precision, --energy-factor, --max-strain)");
  }
}

// The study's lanes, as the scene runs them (a fixed-point scene's implicit_euler named so).
std::vector<Lane> stability_lanes(const StabilityOptions& o, const SceneDef& base) {
  std::vector<Lane> lanes = parse_study_lanes(
      o.integrators, "stability searches the step, so a lane takes no @STEP (its :N stays fixed while the step is searched); drop it");
  refuse_adaptive_lanes(lanes, "stability searches the largest stable step, and an adaptive pair chooses its "
                               "own (its error control keeps it stable)");
  follow_scene_solver(lanes, base.implicit);
  return lanes;
}

StabilityStudy plan_stability(const StabilityOptions& o, const SceneDef& base) {
  StabilityStudy study;
  study.lanes = stability_lanes(o, base);
  std::vector<IntegratorKind> kinds;
  for (const Lane& l : study.lanes) kinds.push_back(l.kind), study.names.push_back(l.stepless_spelling());

  std::vector<analysis::SweepScene> scenes = sweep_cases(o, base, study.values);

  analysis::StabilitySpec& spec = study.spec;
  spec.integrators = kinds;
  spec.duration = o.scene.duration ? *o.scene.duration : std::min(base.duration, kStabilityDefaultDuration);
  if (!(spec.duration > 0.0) || !std::isfinite(spec.duration)) throw UsageError("--duration: must be a finite number > 0 s");
  check_stability_memory(o, base, scenes, kinds);
  double smallest_estimate = INFINITY;
  for (analysis::SweepScene& s : scenes) {
    s.scene.duration = spec.duration;
    study.cases.push_back({s.value, build_model(s.scene)});
    smallest_estimate = std::min(smallest_estimate, analysis::estimate_stiffness(study.cases.back().model).dt_with_damping());
  }
  finish_stability_spec(o, base, smallest_estimate, spec);
  return study;
}

std::vector<analysis::StabilityCase> StabilityStudy::refs() const {
  std::vector<analysis::StabilityCase> out;
  for (const StabilityCaseModels& c : cases) {
    out.push_back({c.value, &c.model, {}});
    for (const Lane& lane : lanes) out.back().lane_settings.push_back(clip::lane_settings(c.model, lane));
  }
  return out;
}

}  // namespace clothsim::clip
