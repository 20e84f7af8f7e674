#include "lane.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "echo.h"
#include "core/integrators/method_param.h"
#include "io/csv_cells.h"
#include "scene_def.h"
#include "text.h"

namespace clothsim {

namespace {

bool has_iterations(IntegratorKind kind) { return integrator_info(kind).iterations != IterationControl::None; }

[[noreturn]] void refuse(const std::string& why) { throw LaneError(why); }

// The `:N` and `:KEY=VALUE` items of a lane (`items`: what follows its first ':'), in any order.
// Which method takes which setting is checked once the name is known (parse_lane).
// `adaptive`: the lane names an adaptive pair, whose tolerances lie in (0, 1); a solver's
// residual tolerance lies in (0, kMaxResidualTolerance], as its scene block's does.
void parse_items(const std::string& items, const std::string& typed, Lane& lane, bool& gave_tol, bool adaptive) {
  std::size_t from = 0;
  while (from <= items.size()) {
    const auto colon = items.find(':', from);
    const std::string part = trimmed(items.substr(from, colon == std::string::npos ? std::string::npos : colon - from));
    const auto eq = part.find('=');
    if (eq != std::string::npos) {
      const std::string key = trimmed(part.substr(0, eq)), value = trimmed(part.substr(eq + 1));
      if (key != "tol" && key != "rtol" && key != "atol") {  // a method's own, checked once its name is known
        const std::optional<double> number = parse_number_or_fraction(value);
        if (!number) refuse(in_quotes(value) + " in " + in_quotes(typed) + " is not a number (" + key + "=)");
        for (const auto& [given, _] : lane.params)
          if (given == key) refuse(in_quotes(typed) + " gives " + key + "= twice");
        lane.params.emplace_back(key, *number);
        if (colon == std::string::npos) break;
        from = colon + 1;
        continue;
      }
      const std::optional<double> tol = parse_number_or_fraction(value);
      if (adaptive && (!tol || !(*tol > 0.0 && *tol < 1.0)))
        refuse("the tolerance in " + in_quotes(typed) + " must be a number above 0 and below 1");
      if (!adaptive && (!tol || !(*tol > 0.0 && *tol <= kMaxResidualTolerance)))
        refuse("the tolerance in " + in_quotes(typed) + " must be a number above 0 and at most " +
               number_text(kMaxResidualTolerance));
      double& slot = key == "rtol" ? lane.rtol : key == "atol" ? lane.atol : lane.tolerance;
      if (slot > 0.0 || (key == "tol" && gave_tol)) refuse(in_quotes(typed) + " gives " + key + "= twice");
      if (key == "tol") gave_tol = true;
      slot = *tol;
    } else {
      if (lane.iterations > 0) refuse(in_quotes(typed) + " gives the iterations twice");
      lane.iterations = parse_iteration_count(part, "the iterations in " + in_quotes(typed));
    }
    if (colon == std::string::npos) break;
    from = colon + 1;
  }
}

// ":N", ":tol=T" or ":N:tol=T" as the lane was given, "" for neither; an adaptive pair's
// ":tol=T" (rtol and atol equal) or ":rtol=R:atol=A". Values in their shortest exact form
// (io/csv_cells.h), so a spelling parses back to this very lane: "beta=0.3", never a rounding.
std::string items_text(const Lane& l) {
  std::string s = l.iterations > 0 ? ":" + std::to_string(l.iterations) : "";
  if (l.tolerance > 0.0) s += ":tol=" + csv_number(l.tolerance);
  for (const auto& [key, value] : l.params) s += ":" + key + "=" + csv_number(value);
  if (l.rtol > 0.0 && l.rtol == l.atol) return s + ":tol=" + csv_number(l.rtol);
  if (l.rtol > 0.0) s += ":rtol=" + csv_number(l.rtol);
  if (l.atol > 0.0) s += ":atol=" + csv_number(l.atol);
  return s;
}

std::string method_spelling(const Lane& l) {
  return l.fixed_point ? std::string(kFixedPointName) : std::string(integrator_name(l.kind));
}

}  // namespace

std::string lane_names_joined(std::string_view separator) {
  return integrator_names_joined(separator) + std::string(separator) + std::string(kFixedPointName);
}

int parse_iteration_count(const std::string& text, const std::string& what) {
  const std::string range = "a whole number from 1 to " + std::to_string(kMaxSolverIterations);
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos)
    refuse(what + ": " + in_quotes(text) + " is not " + range);
  const long n = std::stol(text);
  if (n < 1 || n > kMaxSolverIterations) refuse(what + ": " + text + " is not " + range);
  return static_cast<int>(n);
}

Lane parse_lane(const std::string& typed, bool integrators_only) {
  Lane lane;
  bool gave_tol = false;
  const auto colon = typed.find(':');
  const std::string head = trimmed(typed.substr(0, colon));
  const auto at = head.find('@');
  const std::string name = trimmed(head.substr(0, at));
  const std::optional<IntegratorKind> named = parse_integrator(name);
  if (colon != std::string::npos)
    parse_items(typed.substr(colon + 1), typed, lane, gave_tol, named && integrator_info(*named).adaptive);
  const bool fixed_point = !integrators_only && name == kFixedPointName;
  const std::optional<IntegratorKind> kind = fixed_point ? kBackwardEuler : parse_integrator(name);
  if (!kind)
    refuse("unknown integrator " + in_quotes(name) + " (expected one of: " +
           (integrators_only ? integrator_names_joined() : lane_names_joined() + ", or course") + ")");
  lane.kind = *kind;
  lane.fixed_point = fixed_point;
  if (lane.iterations > 0 && !has_iterations(*kind))
    refuse(name + " has no iterations to set (in " + in_quotes(typed) + ")");
  const bool adaptive = integrator_info(*kind).adaptive;
  if (adaptive && lane.tolerance > 0.0) {  // an adaptive pair's tol= is its rtol and atol
    if (lane.rtol > 0.0 || lane.atol > 0.0)
      refuse(in_quotes(typed) + " gives tol= and rtol= or atol=: tol= sets both");
    lane.rtol = lane.atol = lane.tolerance;
    lane.tolerance = 0.0;
  }
  if (lane.tolerance > 0.0 && (!is_iterative_solver(*kind) || fixed_point))
    refuse(name + " has no residual tolerance to set (in " + in_quotes(typed) +
           "; tol= is for xpbd, projective_dynamics and vbd, and the adaptive pairs bs3, dopri5, rkf78)");
  for (const auto& [key, value] : lane.params) {
    const std::string_view takes = integrator_info(*kind).parameters;
    if (!takes_method_param(*kind, key))
      refuse(name + " has no parameter " + in_quotes(key) + " (in " + in_quotes(typed) + "; " +
             (takes.empty() ? name + " takes none" : name + " takes " + std::string(takes)) +
             "; a lane takes :N, tol=, rtol=, atol= besides)");
    if (const std::string problem = method_param_problem(key, value); !problem.empty())
      refuse(name + ": " + problem + ", got " + number_text(value) + " (in " + in_quotes(typed) + ")");
  }
  if ((lane.rtol > 0.0 || lane.atol > 0.0) && !adaptive)
    refuse(name + " has no error control to set (in " + in_quotes(typed) +
           "; rtol= and atol= are for the adaptive pairs bs3, dopri5 and rkf78)");
  if (at != std::string::npos) {
    const std::string step = trimmed(head.substr(at + 1));
    if (step.empty()) refuse(in_quotes(head) + " has no step after '@'");
    const std::optional<double> dt = parse_number_or_fraction(step);
    if (!dt) refuse(in_quotes(step) + " in " + in_quotes(head) + " is not a number (or a fraction like 1/60)");
    if (!(*dt > 0.0)) refuse("the step in " + in_quotes(head) + " must be > 0 s");
    lane.dt = *dt;
    lane.step_text = step;
    lane.step_from = StepFrom::Written;
  }
  return lane;
}

std::vector<Lane> parse_lane_list(const std::string& text) {
  std::vector<Lane> lanes;
  for (const std::string& raw : split_list(text)) {
    const std::string item = trimmed(raw);
    if (item.empty()) refuse("empty item in " + in_quotes(text));
    if (item == "course") {  // the course framework's four, in its order
      for (IntegratorKind k : comparison_integrators()) {  // backward Euler as the course's fixed point
        Lane l;
        l.kind = k;
        l.fixed_point = k == kBackwardEuler;
        lanes.push_back(l);
      }
      continue;
    }
    lanes.push_back(parse_lane(item));
  }
  if (lanes.empty()) refuse("empty list, no integrator given (expected names such as rk4,implicit_euler@1/60)");
  return lanes;
}

bool Lane::same_as(const Lane& o) const {
  return kind == o.kind && dt == o.dt && fixed_point == o.fixed_point && iterations == o.iterations &&
         tolerance == o.tolerance && rtol == o.rtol && atol == o.atol && params == o.params;
}

std::string Lane::name() const {
  std::string n = std::string(integrator_name(kind)) + items_text(*this);
  if (fixed_point) return n + " (fixed point)";
  if (newton_capped() && iterations == 1) return n + " (Baraff & Witkin)";
  return n;
}

std::string Lane::label() const { return integrator_label(name(), step_text); }

std::string Lane::spelling() const { return method_spelling(*this) + "@" + step_text + items_text(*this); }

std::string Lane::stepless_spelling() const { return method_spelling(*this) + items_text(*this); }

void apply_lane(SceneDef& scene, const Lane& lane) {
  scene.integrator = lane.kind;
  if (lane.written_step()) scene.dt = lane.dt;
  for (const auto& [key, value] : lane.params) set_method_param(scene.methods, key, value);
  if (lane.rtol > 0.0) scene.adaptive.rtol = lane.rtol;
  if (lane.atol > 0.0) scene.adaptive.atol = lane.atol;
  if (lane.fixed_point) {  // the course framework's "implicit" (docs/integrators.md)
    scene.implicit.solver = ImplicitSolver::FixedPoint;
    scene.implicit.fixed_point_iterations = lane.iterations > 0 ? lane.iterations : 1;
    return;
  }
  if (lane.tolerance > 0.0) {
    *residual_tolerance(scene.implicit, scene.solvers, lane.kind) = lane.tolerance;
    *iteration_count(scene.implicit, scene.solvers, lane.kind) = lane.iterations > 0 ? lane.iterations : kToleranceCap;
    return;
  }
  if (lane.iterations > 0) {
    const bool fixed = lane.kind == kBackwardEuler && scene.implicit.solver == ImplicitSolver::FixedPoint;
    *(fixed ? &scene.implicit.fixed_point_iterations : iteration_count(scene.implicit, scene.solvers, lane.kind)) =
        lane.iterations;
  }
}

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

std::string integrator_label(std::string_view name, std::string_view step) {
  return std::string(name) + "  dt = " + std::string(step) + " s";
}

}  // namespace clothsim
