// Symplectic (semi-implicit) Euler on the whole state:
//     v_{n+1} = v_n + h a(x_n, v_n),   x_{n+1} = x_n + h v_{n+1}.
// What the seed report's "explicit Euler" code actually does. First order, but symplectic:
// for x'' = -w^2 x the step matrix has determinant 1, so energy stays bounded (oscillating
// about its true value) as long as w h < 2, and the method blows up beyond.
#include "integrator.h"
#include "core/model/forces.h"

namespace clothsim {

StepStats symplectic_euler_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  const double strain = accelerations(model, state.x, state.v, state.inv_mass, ws.a);  // a_n
  state.v += h * ws.a;
  state.x += h * state.v;  // the new velocity: this is what makes it symplectic
  StepStats stats;
  stats.force_evals = 1;
  stats.start_strain = strain;
  return stats;
}

}  // namespace clothsim
