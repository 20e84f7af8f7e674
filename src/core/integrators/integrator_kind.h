// The integrators by name. The enum is what a scene's `integrator:` key and the
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
  Xpbd,             // Macklin et al. 2016 compliant constraints        ~1 spring pass / iteration
  ProjectiveDynamics,  // Liu et al. 2013 local-global on Phi          pass + factored solve / iteration
  Vbd,              // Chen et al. 2024 vertex block descent on Phi    ~1 spring pass / iteration
};

// Whether the kind is one of the iterative solvers whose iteration count a scene block,
// --iterations and a lane's `:N` set (xpbd, projective_dynamics, vbd).
bool is_iterative_solver(IntegratorKind kind);

// Everything said about an integrator outside its step function, in one table (the
// registry, integrators/integrator.cpp), which names, help texts and default lists read.
struct IntegratorInfo {
  IntegratorKind kind;
  std::string_view name;         // scene/CLI spelling
  int nominal_force_evals;       // per step; 0 where the solve decides (implicit_euler)
  int comparison_slot;           // place in compare's, bench's and stability's default four
                                 // (1..4, the course's order), 0: not among them
  std::string_view description;  // one line, for --help
};
const std::vector<IntegratorInfo>& integrator_registry();  // in enum order

std::string_view integrator_name(IntegratorKind kind);
std::optional<IntegratorKind> parse_integrator(std::string_view name);
const std::vector<IntegratorKind>& all_integrators();
std::string integrator_names_joined(std::string_view separator = ", ");  // for errors and help
std::string default_comparison_list();  // the default four, comma-separated

}  // namespace clothsim
