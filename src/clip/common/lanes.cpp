#include "lanes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "cli_common.h"
#include "clip/compare/compare_plan.h"
#include "clip/frames/overlay_text.h"
#include "scene/echo.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

namespace {

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// The course's "implicit" as a lane of its own: implicit_euler as one fixed-point iteration.

std::string names_or_course() {
  return integrator_names_joined() + ", " + std::string(kFixedPointName) + ", or course";
}

bool has_iterations(IntegratorKind kind) { return integrator_info(kind).iterations != IterationControl::None; }

struct Item {
  LaneSpec lane;
  bool has_step = false;
};

// The `:N` and `:tol=T` suffixes of an item (`suffixes` after its first ':'), in either order.
void parse_suffixes(const std::string& suffixes, const std::string& typed, const std::string& option, LaneSpec& lane) {
  std::size_t from = 0;
  while (from <= suffixes.size()) {
    const auto colon = suffixes.find(':', from);
    const std::string part = trimmed(suffixes.substr(from, colon == std::string::npos ? std::string::npos : colon - from));
    if (part.rfind("tol=", 0) == 0) {
      const std::optional<double> tol = parse_number_or_fraction(trimmed(part.substr(4)));
      if (!tol || !(*tol > 0.0 && *tol < 1.0))
        throw UsageError(option + ": the tolerance in " + in_quotes(typed) + " must be a number above 0 and below 1");
      if (lane.tolerance > 0.0) throw UsageError(option + ": " + in_quotes(typed) + " gives tol= twice");
      lane.tolerance = *tol;
    } else {
      if (lane.iterations > 0) throw UsageError(option + ": " + in_quotes(typed) + " gives the iterations twice");
      lane.iterations = parse_iteration_count(part, option + ": the iterations in " + in_quotes(typed));
    }
    if (colon == std::string::npos) break;
    from = colon + 1;
  }
}

// One NAME[@STEP][:N][:tol=T] item of `option`.
Item parse_item(const std::string& typed, const std::string& option) {
  Item out;
  const auto colon = typed.find(':');
  const std::string item = trimmed(typed.substr(0, colon));
  if (colon != std::string::npos) parse_suffixes(typed.substr(colon + 1), typed, option, out.lane);
  const auto at = item.find('@');
  const std::string name = trimmed(item.substr(0, at));
  const bool lanes = option != "--reference";  // the reference is one of the integrators as the scene sets them
  const bool fixed_point = lanes && name == kFixedPointName;
  const std::optional<IntegratorKind> kind = fixed_point ? kBackwardEuler : parse_integrator(name);
  if (!kind)
    throw UsageError(option + ": unknown integrator " + in_quotes(name) + " (expected one of: " +
                     (lanes ? names_or_course() : integrator_names_joined()) + ")");
  out.lane.kind = *kind;
  out.lane.fixed_point = fixed_point;
  if (out.lane.iterations > 0 && !has_iterations(*kind))
    throw UsageError(option + ": " + name + " has no iterations to set (in " + in_quotes(typed) + ")");
  if (out.lane.tolerance > 0.0 && (!is_iterative_solver(*kind) || fixed_point))
    throw UsageError(option + ": " + name + " has no residual tolerance to set (in " + in_quotes(typed) +
                     "; tol= is for xpbd, projective_dynamics and vbd)");
  if (at != std::string::npos) {
    const std::string step = trimmed(item.substr(at + 1));
    if (step.empty()) throw UsageError(option + ": " + in_quotes(item) + " has no step after '@'");
    const std::optional<double> dt = parse_number_or_fraction(step);
    if (!dt) throw UsageError(option + ": " + in_quotes(step) + " in " + in_quotes(item) +
                              " is not a number (or a fraction like 1/60)");
    if (!(*dt > 0.0)) throw UsageError(option + ": the step in " + in_quotes(item) + " must be > 0 s");
    out.lane.dt = *dt;
    out.lane.step_text = step;
    out.has_step = true;
  }
  return out;
}

bool same_lane(const LaneSpec& a, const LaneSpec& b) {
  return a.kind == b.kind && a.dt == b.dt && a.fixed_point == b.fixed_point &&
         a.iterations == b.iterations && a.tolerance == b.tolerance;
}

}  // namespace

std::string step_string(double dt) {
  std::string text = number_text(dt);
  // A step of one n-th of a second that %g can only round (1/30 s: "0.0333333") is written
  // as the fraction a user gives it in (--dt 1/30, as @1/30 is shown as written).
  const double n = std::round(1.0 / dt);
  std::string digits = text.substr(0, text.find('e'));  // the significant digits %g printed
  digits.erase(std::remove(digits.begin(), digits.end(), '.'), digits.end());
  digits.erase(0, digits.find_first_not_of('0'));
  // (within rounding of 1/n only: 0.033333333333333 is not 1/30, and must not be named so)
  if (digits.size() >= 6 && n >= 2.0 && n < 1e6 && std::abs(n * dt - 1.0) <= 4.0 * std::numeric_limits<double>::epsilon())
    return "1/" + number_text(n);
  return text;
}

namespace {
// ":N", ":tol=T" or ":N:tol=T" as the lane was given, "" for neither.
std::string suffix_text(int iterations, double tolerance) {
  std::string s = iterations > 0 ? ":" + std::to_string(iterations) : "";
  return tolerance > 0.0 ? s + ":tol=" + number_text(tolerance) : s;
}
}  // namespace

std::string LaneSpec::name() const {
  std::string n = std::string(integrator_name(kind)) + suffix_text(iterations, tolerance);
  if (fixed_point) return n + " (fixed point)";
  if (newton_capped() && iterations == 1) return n + " (Baraff & Witkin)";
  return n;
}

std::string LaneSpec::label() const { return integrator_label(name(), step_text); }

std::string LaneSpec::spelling() const {
  return (fixed_point ? std::string(kFixedPointName) : std::string(integrator_name(kind))) + "@" + step_text +
         suffix_text(iterations, tolerance);
}

std::string LaneSpec::stepless_spelling() const {
  return (fixed_point ? std::string(kFixedPointName) : std::string(integrator_name(kind))) +
         suffix_text(iterations, tolerance);
}

std::vector<LaneSpec> parse_study_lanes(const std::string& integrators, const std::string& why_no_step) {
  const std::vector<std::string> items = split_list(integrators);
  std::vector<LaneSpec> lanes;
  for (const std::string& raw : items) {
    const std::string item = trimmed(raw);
    if (item.find('@') != std::string::npos) throw UsageError("--integrators: " + in_quotes(item) + ": " + why_no_step);
    if (item.empty()) return parse_lanes(integrators, "", 1.0);  // its message for an empty item
  }
  if (items.empty()) return parse_lanes(integrators, "", 1.0);  // its message for an empty list
  for (const std::string& raw : items)  // the step is the study's, not the lane's: 1 s stands in
    for (const LaneSpec& lane : parse_lanes(trimmed(raw), "", 1.0)) {
      for (const LaneSpec& l : lanes)
        if (l.stepless_spelling() == lane.stepless_spelling())
          throw UsageError("--integrators: " + in_quotes(lane.stepless_spelling()) + " is listed twice");
      lanes.push_back(lane);
    }
  return lanes;
}

int parse_iteration_count(const std::string& text, const std::string& what) {
  const std::string range = "a whole number from 1 to " + std::to_string(kMaxSolverIterations);
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos)
    throw UsageError(what + ": " + in_quotes(text) + " is not " + range);
  const long n = std::stol(text);
  if (n < 1 || n > kMaxSolverIterations) throw UsageError(what + ": " + text + " is not " + range);
  return static_cast<int>(n);
}

void set_tolerance(Model& model, IntegratorKind kind, double tolerance, int cap) {
  double* tol = residual_tolerance(model, kind);
  if (!tol) return;  // refused when parsed
  *tol = tolerance;
  *iteration_count(model, kind) = cap;
}

void set_iterations(Model& model, IntegratorKind kind, bool fixed_point, int iterations,
                    const std::string& what) {
  const bool fixed = kind == kBackwardEuler && (fixed_point || model.implicit.solver == ImplicitSolver::FixedPoint);
  int* count = fixed ? &model.implicit.fixed_point_iterations : iteration_count(model, kind);
  if (!count) throw UsageError(what + ": " + std::string(integrator_name(kind)) + " has no iterations to set");
  *count = iterations;
}

std::vector<LaneSpec> parse_lanes(const std::string& integrators, const std::string& dt_text, double scene_dt) {
  std::vector<Item> items;
  for (const std::string& raw : split_list(integrators)) {
    const std::string item = trimmed(raw);
    if (item.empty()) throw UsageError("--integrators: empty item in " + in_quotes(integrators));
    if (item == "course") {  // the course framework's four, in its order
      for (IntegratorKind k : comparison_integrators())  // backward Euler as the course's fixed point
        items.push_back(Item{LaneSpec{k, 0.0, "", k == kBackwardEuler}, false});
      continue;
    }
    items.push_back(parse_item(item, "--integrators"));
  }
  if (items.empty())
    throw UsageError("--integrators: empty list, no integrator given (expected names such as rk4,implicit_euler@1/60)");

  // Lanes without @STEP take --dt as before: per integrator, or one step for all of them.
  std::vector<IntegratorKind> stepless;
  for (const Item& i : items)
    if (!i.has_step && std::find(stepless.begin(), stepless.end(), i.lane.kind) == stepless.end())
      stepless.push_back(i.lane.kind);
  const std::vector<double> dts = parse_dt_list(dt_text, stepless, scene_dt);
  std::vector<LaneSpec> lanes;
  for (Item& i : items) {
    if (!i.has_step) {
      i.lane.dt = dts[static_cast<std::size_t>(std::find(stepless.begin(), stepless.end(), i.lane.kind) - stepless.begin())];
      i.lane.step_text = step_string(i.lane.dt);
    }
    for (const LaneSpec& l : lanes)
      if (same_lane(l, i.lane))
        throw UsageError("--integrators: " + in_quotes(i.lane.spelling()) +
                         " is listed twice (the same integrator at the same step)");
    lanes.push_back(i.lane);
  }
  return lanes;
}

double smallest_step(const std::vector<LaneSpec>& lanes) {
  double smallest = lanes.front().dt;
  for (const LaneSpec& l : lanes) smallest = std::min(smallest, l.dt);
  return smallest;
}

LaneSpec parse_reference(const std::string& text, const std::vector<LaneSpec>& lanes) {
  LaneSpec ref{kReferenceIntegrator, smallest_step(lanes) / 4.0, "", false};
  if (!trimmed(text).empty()) {
    if (text.find(',') != std::string::npos) throw UsageError("--reference: one lane, got " + in_quotes(text));
    const Item item = parse_item(trimmed(text), "--reference");
    ref.kind = item.lane.kind;
    if (item.has_step) {
      ref.dt = item.lane.dt;
      ref.step_text = item.lane.step_text;
    }
  }
  if (ref.step_text.empty()) ref.step_text = step_string(ref.dt);
  return ref;
}

void follow_scene_solver(std::vector<LaneSpec>& lanes, const ImplicitDef& implicit) {
  if (implicit.solver != ImplicitSolver::FixedPoint) return;
  for (LaneSpec& l : lanes) {
    if (l.kind != kBackwardEuler || l.fixed_point) continue;
    l.fixed_point = true;  // lane_model sets one iteration unless the lane says how many
    if (l.iterations == 0 && implicit.fixed_point_iterations != 1) l.iterations = implicit.fixed_point_iterations;
  }
}

const Model& lane_model(const Model& base, const LaneSpec& lane, std::optional<Model>& storage) {
  const std::string refused = base.collision.model == ContactModel::Barrier ? barrier_refusal(lane.kind) : "";
  if (!refused.empty()) throw UsageError("--integrators: collision.model: barrier: " + refused);
  if (!lane.fixed_point && lane.iterations == 0 && lane.tolerance == 0.0) return base;
  storage.emplace(base);
  if (lane.fixed_point) {  // the course framework's "implicit" (docs/integrators.md)
    storage->implicit.solver = ImplicitSolver::FixedPoint;
    storage->implicit.fixed_point_iterations = 1;
  }
  if (lane.tolerance > 0.0) set_tolerance(*storage, lane.kind, lane.tolerance, lane.iterations > 0 ? lane.iterations : kToleranceCap);
  if (lane.iterations > 0)
    set_iterations(*storage, lane.kind, lane.fixed_point, lane.iterations, "--integrators");
  return *storage;
}

std::vector<std::string> lane_directories(const std::vector<LaneSpec>& lanes) {
  std::vector<std::string> dirs;
  for (const LaneSpec& l : lanes) {
    const auto same_kind = std::count_if(lanes.begin(), lanes.end(), [&](const LaneSpec& o) { return o.kind == l.kind; });
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
