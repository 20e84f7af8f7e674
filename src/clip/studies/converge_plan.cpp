#include "converge_plan.h"

#include <optional>

#include "clip/common/cli_common.h"
#include "clip/common/lanes.h"
#include "scene/echo.h"

namespace clothsim::clip {

std::vector<IntegratorKind> parse_methods(const std::string& text) {
  std::vector<IntegratorKind> out;
  for (const std::string& name : split_list(text)) {
    const auto kind = parse_integrator(name);
    if (!kind || integrator_info(*kind).iterations == IterationControl::None)
      throw UsageError("--integrators: " + in_quotes(name) +
                       " is not an iterative method (expected xpbd, projective_dynamics, vbd or implicit_euler)");
    // The implicit family iterates Newton too, but toward its own step, not backward Euler's,
    // which is the one converge measures every method against.
    if (*kind != kBackwardEuler && !is_iterative_solver(*kind))
      throw UsageError("--integrators: " + in_quotes(name) + " converges to its own step, not to backward Euler's, "
                       "which converge measures against (expected xpbd, projective_dynamics, vbd or implicit_euler)");
    out.push_back(*kind);
  }
  if (out.empty()) throw UsageError("--integrators: no method given");
  return out;
}

ConvergenceSpec plan_converge(const ConvergeOptions& o) {
  ConvergenceSpec spec;
  const std::optional<double> h = parse_number_or_fraction(o.dt);
  if (!h || !(*h > 0.0)) throw UsageError("--dt: " + in_quotes(o.dt) + " is not a step > 0 s (a number or 1/60)");
  spec.h = *h;
  spec.states = parse_iteration_option(o.states, "--states");
  spec.max_iterations = parse_iteration_option(o.max_iterations, "--max-iterations");
  spec.methods = parse_methods(o.integrators);
  return spec;
}

}  // namespace clothsim::clip
