#include "converge_plan.h"

#include <optional>

#include "clip/common/cli_common.h"
#include "clip/common/lanes.h"
#include "scene/echo.h"

namespace clothsim::clip {

// The methods converge measures: every one that iterates (the solvers, and Newton's:
// implicit_euler and the implicit family, each against its own converged step).
std::string iterative_names() {
  std::vector<std::string> names;
  for (const IntegratorInfo& info : integrator_registry())
    if (info.iterations != IterationControl::None) names.emplace_back(info.name);
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return out;
}

std::vector<IntegratorKind> parse_methods(const std::string& text) {
  std::vector<IntegratorKind> out;
  for (const std::string& name : split_list(text)) {
    const auto kind = parse_integrator(name);
    if (!kind || integrator_info(*kind).iterations == IterationControl::None)
      throw UsageError("--integrators: " + in_quotes(name) + " is not an iterative method (expected " +
                       iterative_names() + ")");
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
