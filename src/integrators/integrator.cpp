// The dispatch: one switch, one function per method (MuJoCo's mj_step pattern).
#include "integrator.h"

#include <stdexcept>

namespace clothsim {

StepStats integrate(IntegratorKind kind, const Model& model, State& state, double h,
                    Workspace& ws) {
  switch (kind) {
    case IntegratorKind::ExplicitEuler: return explicit_euler_step(model, state, h, ws);
    case IntegratorKind::SymplecticEuler: return symplectic_euler_step(model, state, h, ws);
    case IntegratorKind::Midpoint: return midpoint_step(model, state, h, ws);
    case IntegratorKind::Rk4: return rk4_step(model, state, h, ws);
    case IntegratorKind::ImplicitEuler: return implicit_euler_step(model, state, h, ws);
  }
  throw std::logic_error("integrate: unknown integrator");
}

int nominal_force_evals(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::ExplicitEuler: return 1;
    case IntegratorKind::SymplecticEuler: return 1;
    case IntegratorKind::Midpoint: return 2;
    case IntegratorKind::Rk4: return 4;
    case IntegratorKind::ImplicitEuler: return 0;
  }
  return 0;
}

}  // namespace clothsim
