#include "bench_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "clip/common/cli_common.h"
#include "clip/common/memory_budget.h"
#include "clip/common/plan_parts.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/echo.h"
#include "scene/scene_parser.h"
#include "study/scale_study.h"
#include "study/task_pool.h"

namespace clothsim::clip {

std::vector<Lane> bench_lanes(const BenchOptions& o, const SceneDef& scene) {
  std::vector<Lane> lanes =
      parse_study_lanes(o.integrators, "bench sweeps the step (--dts), so a lane takes no @STEP; drop it");
  for (const Lane& l : lanes)
    if (integrator_info(l.kind).adaptive && (l.rtol > 0.0 || l.atol > 0.0))
      throw UsageError("--integrators: " + in_quotes(l.spelling()) +
                       ": bench sweeps an adaptive lane's tolerance (--tols), so it takes no :tol=, :rtol= or :atol=; drop it");
  const bool adaptive = std::any_of(lanes.begin(), lanes.end(), [](const Lane& l) { return integrator_info(l.kind).adaptive; });
  if (o.tols && !adaptive)
    throw UsageError("--tols: no adaptive lane to sweep (bs3, dopri5 or rkf78 in --integrators); fixed steps take --dts");
  follow_scene_solver(lanes, scene.implicit);  // --set implicit.solver=fixed_point: named as itself
  return lanes;
}

double default_duration(double scene_duration, const std::vector<double>& dts) {
  const double smallest = *std::min_element(dts.begin(), dts.end());
  const double largest = *std::max_element(dts.begin(), dts.end());
  const double cap = std::min({scene_duration, kMaxDefaultDuration, kMaxDefaultSmallSteps * smallest});
  const double whole = std::floor(cap / largest + 1e-9);
  if (whole < 1.0) {
    char msg[200];
    std::snprintf(msg, sizeof msg, "--dts: the largest step %g s is longer than the default duration %g s; "
                  "give --duration", largest, cap);
    throw UsageError(msg);
  }
  return whole * largest;
}

WorkPrecisionSpec plan_bench(const BenchOptions& o, const SceneDef& scene, const std::vector<Lane>& lanes) {
  if (o.error != "time" && o.error != "end")
    throw UsageError("--error: expected time (the largest over the sample times) or end (at T), got " + in_quotes(o.error));
  std::vector<double> dts;
  if (!o.dts) {
    for (double f : kDefaultStepFactors) dts.push_back(f * scene.dt);
  } else {
    dts = parse_number_list(*o.dts, "--dts");
    for (double dt : dts)
      if (!(dt > 0.0)) throw UsageError("--dts: " + csv_number(dt) + " is not a positive step (s)");
  }
  double T = 0.0;
  if (o.scene.duration) {
    T = *o.scene.duration;
    if (!(T > 0.0) || !std::isfinite(T)) throw UsageError("--duration: must be a finite number > 0 s");
  } else {
    T = default_duration(scene.duration, dts);
  }
  if (o.jobs < 0) throw UsageError("--jobs: must be >= 0 (0: one per core)");
  if (o.reference_refinement < 1) throw UsageError("--reference-refinement: must be >= 1");

  WorkPrecisionSpec spec;
  for (const Lane& l : lanes) {
    spec.integrators.push_back(l.kind);
    spec.lane_names.push_back(l.stepless_spelling());
  }
  spec.dts = dts;
  if (std::any_of(lanes.begin(), lanes.end(), [](const Lane& l) { return integrator_info(l.kind).adaptive; })) {
    if (o.tols) spec.tolerances = parse_number_list(*o.tols, "--tols");
    else spec.tolerances.assign(std::begin(kDefaultTolerances), std::end(kDefaultTolerances));
    for (std::size_t i = 0; i < spec.tolerances.size(); ++i) {
      const double tol = spec.tolerances[i];
      if (!(tol > 0.0 && tol < 1.0)) throw UsageError("--tols: " + csv_number(tol) + " is not a tolerance in (0, 1)");
      if (std::find(spec.tolerances.begin(), spec.tolerances.begin() + i, tol) != spec.tolerances.begin() + i)
        throw UsageError("--tols: " + csv_number(tol) + " is listed twice");
    }
    spec.first_step = scene.dt;  // the first trial step, as a compare lane of the pair takes it
  }
  // One step per video frame for implicit Euler, where it divides T (the default T of a short
  // study may not be a multiple of 1/30 s: those steps are left out, and said so).
  for (double dt : parse_frame_dts(o.frame_dts)) {
    const double n = T / dt;
    if (std::abs(n - std::round(n)) <= 1e-9 * n && std::round(n) >= 1) spec.frame_dts.push_back(dt);
    else std::fprintf(stderr, "bench: frame step %g s does not divide T = %g s; left out\n", dt, T);
  }
  spec.duration = T;
  spec.jobs = o.jobs;
  spec.error_over_time = o.error == "time";
  spec.reference_refinement = o.reference_refinement;
  if (!(o.reference_tolerance > 0.0) || !(o.reference_tolerance < 1e-3))
    throw UsageError("--reference-tolerance: must be a number in (0, 1e-3)");
  spec.reference_tolerance = o.reference_tolerance;
  if (!o.no_reference_cache) {  // the reference of a scene, kept between runs (study/reference_cache.h)
    try {
      spec.reference_cache = analysis::reference_cache_settings();
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  try {
    return analysis::checked(spec);
  } catch (const analysis::StudyError& e) {
    const std::string what = e.what();
    throw UsageError((what.rfind("tolerance", 0) == 0 ? "--tols: " : "--dts: ") + what);
  }
}

void check_bench_memory(const BenchOptions& o, const SceneDef& scene, const std::vector<IntegratorKind>& kinds) {
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  double dearest = 0.0;
  for (IntegratorKind k : kinds) dearest = std::max(dearest, run_bytes(scene, k));
  const int threads = analysis::resolve_jobs(o.jobs);
  budget.add(std::to_string(threads) + " runs at once", threads * dearest);
  budget.check(scene.source, o.scene.max_memory);
}

std::vector<ValueStudy> plan_values(const BenchOptions& o, const SceneDef& base, const std::vector<Lane>& lanes) {
  if (!o.summary.empty() || !o.shard.empty())
    throw UsageError("--vary: --summary and --shard take one scene's study; give --csv (and --plot) with --vary");
  const Variation v = parse_vary(o.vary, base);
  std::vector<ValueStudy> studies;
  for (std::size_t value = 0; value < v.size(); ++value) {  // every scene read (a bad value named) before any run
    ValueStudy s;
    s.label = v.label(value);
    std::vector<std::string> sets = o.scene.sets;
    for (const std::string& set : v.sets(value)) sets.push_back(set);
    try {  // a bad key or value: the parser's message, said of --vary as typed
      s.scene = load_scene(o.scene.path, sets);
    } catch (const SceneError& e) {
      throw as_option_error(e, v.key, "--vary " + o.vary);
    }
    for (const Lane& l : lanes) s.names.push_back(l.stepless_spelling() + " (" + s.label + ")");
    s.spec = plan_bench(o, s.scene, lanes);  // bad --dts or --duration before any run
    s.spec.lane_names = s.names;
    studies.push_back(std::move(s));
  }
  return studies;
}

Model build_bench_model(const BenchOptions& o, SceneDef& scene, const std::vector<Lane>& lanes,
                        const WorkPrecisionSpec& spec) {
  scene.duration = std::max(scene.duration, spec.duration);
  std::vector<IntegratorKind> kinds;
  for (const Lane& l : lanes) kinds.push_back(l.kind);
  check_bench_memory(o, scene, kinds);
  return build_model(scene);
}

void attach_lane_settings(const Model& model, const std::vector<Lane>& lanes, WorkPrecisionSpec& spec) {
  spec.lane_settings.clear();
  for (const Lane& lane : lanes) spec.lane_settings.push_back(clip::lane_settings(model, lane));
}

BenchModels::BenchModels(const BenchOptions& o, SceneDef& scene, const std::vector<Lane>& lanes,
                         WorkPrecisionSpec plan)
    : model(build_bench_model(o, scene, lanes, plan)), spec(std::move(plan)) {
  attach_lane_settings(model, lanes, spec);
}

ScalePlan plan_scale(const BenchOptions& o) {
  if (!o.summary.empty() || !o.shard.empty() || !o.vary.empty() || o.dts)
    throw UsageError("--scale: give lanes as NAME@STEP; --dts, --vary, --summary and --shard do not apply");
  ScalePlan plan;
  for (double n : parse_number_list(o.scale, "--scale")) {
    if (n != std::floor(n)) throw UsageError("--scale: " + csv_number(n) + " is not a whole number of particles");
    plan.sides.push_back(static_cast<int>(n));
  }
  analysis::ScaleSpec& spec = plan.spec;
  try {
    spec.sizes = analysis::scale_scenes(o.scene.path, o.scene.sets, plan.sides);
  } catch (const analysis::StudyError& e) {
    throw UsageError(std::string("--scale: ") + e.what());
  }
  const SceneDef& first = spec.sizes.front().scene;
  auto lanes = std::make_shared<const std::vector<Lane>>(parse_lanes(o.integrators, "", first.dt));
  for (const Lane& l : *lanes) spec.lanes.push_back({l.spelling(), l.kind, l.dt});
  spec.lane_settings = [lanes](const Model& model, std::size_t i) { return clip::lane_settings(model, (*lanes)[i]); };
  plan.lanes = std::move(lanes);
  spec.duration = o.scene.duration ? *o.scene.duration : std::min(first.duration, kMaxScaleDuration);
  if (!(spec.duration > 0.0) || !std::isfinite(spec.duration)) throw UsageError("--duration: must be a finite number > 0 s");
  return plan;
}

void check_scale_memory(const BenchOptions& o, const ScalePlan& plan) {
  std::vector<IntegratorKind> kinds;
  for (const Lane& l : *plan.lanes) kinds.push_back(l.kind);
  for (const analysis::ScaleScene& s : plan.spec.sizes) check_bench_memory(o, s.scene, kinds);
}

}  // namespace clothsim::clip
