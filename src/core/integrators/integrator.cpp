// The registry and the dispatch: one table, one lookup, one function per method (MuJoCo's
// mj_step pattern). Adding an integrator is one row here and its step function.
#include "integrator.h"

#include <iterator>
#include <stdexcept>

namespace clothsim {
namespace {

using StepFunction = StepStats (*)(const Model&, State&, double, Workspace&);

struct Entry {
  IntegratorInfo info;
  StepFunction step;
};

// In enum order, so an entry is found by the enum's value.
const Entry kRegistry[] = {
    {{IntegratorKind::ExplicitEuler, "explicit_euler", 1, 1,
      "forward Euler: x += h v_n, v += h a_n (the course framework's 'explicit')"},
     explicit_euler_step},
    {{IntegratorKind::SymplecticEuler, "symplectic_euler", 1, 0,
      "v += h a_n, x += h v_{n+1} (the student report's code)"},
     symplectic_euler_step},
    {{IntegratorKind::Midpoint, "midpoint", 2, 3, "RK2 through the half-step state"},
     midpoint_step},
    {{IntegratorKind::Rk4, "rk4", 4, 4, "classic Runge-Kutta 4 on (x, v)"}, rk4_step},
    {{IntegratorKind::ImplicitEuler, "implicit_euler", 0, 2,
      "backward Euler: Newton + PCG, contacts in the solve (or fixed point)"},
     implicit_euler_step},
    {{IntegratorKind::Xpbd, "xpbd", 0, 0,
      "XPBD (Macklin et al. 2016): compliant distance constraints, Gauss-Seidel"},
     xpbd_step},
    {{IntegratorKind::ProjectiveDynamics, "projective_dynamics", 0, 0,
      "projective dynamics (Liu et al. 2013): local-global on Phi, prefactored"},
     projective_dynamics_step},
    {{IntegratorKind::Vbd, "vbd", 0, 0,
      "vertex block descent (Chen et al. 2024): per-vertex Newton on Phi"},
     vbd_step},
};

const Entry& entry(IntegratorKind kind) {
  const auto index = static_cast<std::size_t>(kind);
  if (index >= std::size(kRegistry) || kRegistry[index].info.kind != kind)
    throw std::logic_error("integrator registry: no entry for this kind");
  return kRegistry[index];
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_registry() {
  static const std::vector<IntegratorInfo> infos = [] {
    std::vector<IntegratorInfo> out;
    for (const Entry& e : kRegistry) out.push_back(e.info);
    return out;
  }();
  return infos;
}

StepStats integrate(IntegratorKind kind, const Model& model, State& state, double h,
                    Workspace& ws) {
  return entry(kind).step(model, state, h, ws);
}

int nominal_force_evals(IntegratorKind kind) { return entry(kind).info.nominal_force_evals; }

}  // namespace clothsim
