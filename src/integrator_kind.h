// The five integrators by name. The enum is what a scene's `integrator:` key and the
// CLI's --integrator parse into; the step dispatches on it in integrator.cpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace clothsim {

enum class IntegratorKind {
  ExplicitEuler,    // x += h v_n; v += h a_n                        1 force eval
  SymplecticEuler,  // v += h a_n; x += h v_{n+1}                    1 force eval
  Midpoint,         // RK2 through the half-step state               2 force evals
  Rk4,              // classic Runge-Kutta 4 on (x, v)               4 force evals
  ImplicitEuler,    // backward Euler, Newton + PCG (or fixed point)  1 + solver work
};

// Scene/CLI spelling: explicit_euler, symplectic_euler, midpoint, rk4, implicit_euler.
std::string_view integrator_name(IntegratorKind kind);
std::optional<IntegratorKind> parse_integrator(std::string_view name);
const std::vector<IntegratorKind>& all_integrators();
std::string integrator_names_joined();  // "explicit_euler, symplectic_euler, ..." for errors

}  // namespace clothsim
