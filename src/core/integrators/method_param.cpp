#include "method_param.h"

#include <stdexcept>

#include "integrator_kind.h"

namespace clothsim {

std::string method_param_problem(std::string_view key, double value) {
  const std::string k(key);
  if (key == "beta")
    return value > 0.0 && value <= 0.5 ? "" : k + " must be above 0 and at most 0.5 (0 is explicit: no step to solve)";
  if (key == "gamma")
    return value >= 0.5 && value <= 1.0 ? "" : k + " must be from 0.5 to 1 (below 0.5 the scheme grows)";
  if (key == "rho") return value >= 0.0 && value <= 1.0 ? "" : k + " (rho_inf) must be from 0 to 1";
  return "unknown parameter " + k;
}

void set_method_param(MethodDefs& methods, std::string_view key, double value) {
  if (key == "beta") methods.newmark.beta = value;
  else if (key == "gamma") methods.newmark.gamma = value;
  else if (key == "rho") methods.generalized_alpha.rho_inf = value;
  else throw std::logic_error("set_method_param: unknown parameter " + std::string(key));
}

bool takes_method_param(IntegratorKind kind, std::string_view key) {
  std::string_view list = integrator_info(kind).parameters;
  while (!list.empty()) {
    const auto comma = list.find(',');
    if (list.substr(0, comma) == key) return true;
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return false;
}

}  // namespace clothsim
