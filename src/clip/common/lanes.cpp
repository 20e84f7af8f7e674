#include "lanes.h"

#include <algorithm>
#include <optional>

#include "cli_common.h"
#include "clip/common/plan_parts.h"
#include "scene/echo.h"
#include "core/integrators/integrator_kind.h"
#include "core/integrators/method_param.h"

namespace clothsim::clip {

void refuse_lane(const std::string& option, const LaneError& e) {
  throw UsageError(option.empty() ? std::string(e.what()) : option + ": " + e.what());
}

int parse_iteration_option(const std::string& text, const std::string& option) {
  try {
    return parse_iteration_count(text, option);
  } catch (const LaneError& e) {
    refuse_lane("", e);
  }
}

namespace {

std::vector<Lane> lane_list(const std::string& integrators) {
  try {
    return parse_lane_list(integrators);
  } catch (const LaneError& e) {
    refuse_lane("--integrators", e);
  }
}

}  // namespace

std::vector<Lane> parse_study_lanes(const std::string& integrators, const std::string& why_no_step) {
  std::vector<Lane> lanes;
  for (const Lane& lane : lane_list(integrators)) {  // the step is the study's, not the lane's
    if (lane.written_step())
      throw UsageError("--integrators: " + in_quotes(lane.spelling()) + ": " + why_no_step);
    for (const Lane& l : lanes)
      if (l.stepless_spelling() == lane.stepless_spelling())
        throw UsageError("--integrators: " + in_quotes(lane.stepless_spelling()) + " is listed twice");
    lanes.push_back(lane);
  }
  return lanes;
}

void refuse_adaptive_lanes(const std::vector<Lane>& lanes, const std::string& why) {
  for (const Lane& l : lanes)
    if (integrator_info(l.kind).adaptive)
      throw UsageError("--integrators: " + in_quotes(l.stepless_spelling()) + ": " + why);
}

std::vector<Lane> parse_lanes(const std::string& integrators, const std::string& dt_text, double scene_dt) {
  std::vector<Lane> items = lane_list(integrators);
  // Lanes without @STEP take --dt as before: per integrator, or one step for all of them.
  std::vector<IntegratorKind> stepless;
  for (const Lane& l : items)
    if (!l.written_step() && std::find(stepless.begin(), stepless.end(), l.kind) == stepless.end())
      stepless.push_back(l.kind);
  const std::vector<std::optional<double>> dts = parse_dt_options(dt_text, stepless);
  std::vector<Lane> lanes;
  for (Lane& l : items) {
    if (!l.written_step()) {
      const std::optional<double>& dt =
          dts[static_cast<std::size_t>(std::find(stepless.begin(), stepless.end(), l.kind) - stepless.begin())];
      l.dt = dt.value_or(scene_dt);
      l.step_from = dt ? StepFrom::Option : StepFrom::Scene;
      l.step_text = step_string(l.dt);
    }
    for (const Lane& other : lanes)
      if (other.same_as(l))
        throw UsageError("--integrators: " + in_quotes(l.spelling()) +
                         " is listed twice (the same integrator at the same step)");
    lanes.push_back(l);
  }
  return lanes;
}

Lane parse_reference(const std::string& text, const std::vector<Lane>& lanes) {
  Lane ref;
  ref.kind = kReferenceIntegrator;
  ref.dt = smallest_step(lanes) / 4.0;
  if (!trimmed(text).empty()) {
    if (text.find(',') != std::string::npos) throw UsageError("--reference: one lane, got " + in_quotes(text));
    Lane given;
    try {
      given = parse_lane(trimmed(text), /*integrators_only=*/true);  // the reference is an integrator as the scene sets it
    } catch (const LaneError& e) {
      refuse_lane("--reference", e);
    }
    ref.kind = given.kind;
    if (given.written_step()) ref = Lane{given.kind, given.dt, given.step_text, false, StepFrom::Written};
    if (integrator_info(given.kind).adaptive) {
      // The adaptive reference is one solve, the served dopri5 checked by one 10x tighter
      // (study/reference.h): a tolerance chooses it, a step would not.
      if (given.kind != kAdaptiveReferenceIntegrator)
        throw UsageError("--reference: the adaptive reference is dopri5 (checked by a solve 10x tighter), got " +
                         in_quotes(trimmed(text)) + "; give dopri5 or dopri5:tol=T");
      if (given.written_step())
        throw UsageError("--reference: " + in_quotes(trimmed(text)) +
                         ": the adaptive reference takes a tolerance (dopri5:tol=T), not a step");
      if (given.rtol != given.atol)
        throw UsageError("--reference: " + in_quotes(trimmed(text)) +
                         ": the adaptive reference takes one tolerance for both (dopri5:tol=T)");
      ref.rtol = ref.atol = given.rtol;
    }
  }
  if (ref.step_text.empty()) ref.step_text = step_string(ref.dt);
  return ref;
}

void set_tolerance(MethodSettings& settings, IntegratorKind kind, double tolerance, int cap) {
  double* tol = residual_tolerance(settings, kind);
  if (!tol) return;  // refused when parsed
  *tol = tolerance;
  *iteration_count(settings, kind) = cap;
}

void set_iterations(MethodSettings& settings, IntegratorKind kind, bool fixed_point, int iterations,
                    const std::string& what) {
  ImplicitDef& implicit = settings.implicit;
  const bool fixed = kind == kBackwardEuler && (fixed_point || implicit.solver == ImplicitSolver::FixedPoint);
  int* count = fixed ? &implicit.fixed_point_iterations : iteration_count(settings, kind);
  if (!count) throw UsageError(what + ": " + std::string(integrator_name(kind)) + " has no iterations to set");
  *count = iterations;
}

double smallest_step(const std::vector<Lane>& lanes) {
  double smallest = lanes.front().dt;
  for (const Lane& l : lanes) smallest = std::min(smallest, l.dt);
  return smallest;
}

void follow_scene_solver(std::vector<Lane>& lanes, const ImplicitDef& implicit) {
  if (implicit.solver != ImplicitSolver::FixedPoint) return;
  for (Lane& l : lanes) {
    if (l.kind != kBackwardEuler || l.fixed_point) continue;
    l.fixed_point = true;  // lane_settings sets one iteration unless the lane says how many
    if (l.iterations == 0 && implicit.fixed_point_iterations != 1) l.iterations = implicit.fixed_point_iterations;
  }
}

MethodSettings lane_settings(const Model& base, const Lane& lane) {
  const std::string refused = base.collision.model == ContactModel::Barrier ? barrier_refusal(lane.kind) : "";
  if (!refused.empty()) throw UsageError("--integrators: collision.model: barrier: " + refused);
  MethodSettings s = base.method_defaults();
  for (const auto& [key, value] : lane.params) set_method_param(s.methods, key, value);
  if (lane.rtol > 0.0) s.adaptive.rtol = lane.rtol;  // an adaptive pair's error control
  if (lane.atol > 0.0) s.adaptive.atol = lane.atol;
  if (lane.fixed_point) {  // the course framework's "implicit" (docs/integrators.md)
    s.implicit.solver = ImplicitSolver::FixedPoint;
    s.implicit.fixed_point_iterations = 1;
  }
  if (lane.tolerance > 0.0)
    set_tolerance(s, lane.kind, lane.tolerance, lane.iterations > 0 ? lane.iterations : kToleranceCap);
  if (lane.iterations > 0) set_iterations(s, lane.kind, lane.fixed_point, lane.iterations, "--integrators");
  return s;
}

std::vector<std::string> lane_directories(const std::vector<Lane>& lanes) {
  std::vector<std::string> dirs;
  for (const Lane& l : lanes) {
    const auto same_kind = std::count_if(lanes.begin(), lanes.end(), [&](const Lane& o) { return o.kind == l.kind; });
    std::string d(integrator_name(l.kind));
    if (l.fixed_point) d += "_fixed_point";
    if (same_kind > 1) d += "@" + l.step_text;
    if (same_kind > 1 && l.iterations > 0) d += "_" + std::to_string(l.iterations);
    if (same_kind > 1 && l.tolerance > 0.0) d += "_tol" + number_text(l.tolerance);
    std::replace(d.begin(), d.end(), '/', '_');
    std::replace(d.begin(), d.end(), ' ', '_');
    dirs.push_back(d);
  }
  return dirs;
}

}  // namespace clothsim::clip
