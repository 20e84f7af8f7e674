// Forward (explicit) Euler on the whole state:
//     x_{n+1} = x_n + h v_n,   v_{n+1} = v_n + h a(x_n, v_n).
// First order. For x'' = -w^2 x its amplification factor is 1 + i w h, of modulus
// sqrt(1 + (w h)^2) > 1: an undamped oscillator gains energy at every step size.
#include "integrator.h"
#include "core/model/forces.h"

namespace clothsim {

StepStats explicit_euler_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  const double strain = accelerations(model, state.x, state.v, state.inv_mass, ws.a);  // a_n
  state.x += h * state.v;                                         // with v_n, not v_{n+1}
  state.v += h * ws.a;
  StepStats stats;
  stats.force_evals = 1;
  stats.start_strain = strain;
  return stats;
}

}  // namespace clothsim
