// Explicit midpoint (RK2) on the whole state y = (x, v), y' = F(y) = (v, a(x, v)):
//     y_half  = y_n + (h/2) F(y_n)                 x_half = x_n + (h/2) v_n,  v_half = v_n + (h/2) a_n
//     y_{n+1} = y_n + h F(y_half)                  x_{n+1} = x_n + h v_half,  v_{n+1} = v_n + h a_half
// Second order, two force evaluations. Both components of the full step use the half-step
// derivative (the seed's fragment takes the position step with v_{n+1} and loses the order).
// For x'' = -w^2 x the amplification factor is 1 + z + z^2/2 with z = i w h, of modulus
// sqrt(1 + (w h)^4 / 4) > 1: undamped, it gains energy at every step size, only slowly.
#include "integrator.h"
#include "core/model/forces.h"

namespace clothsim {

StepStats midpoint_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  const double half = 0.5 * h;
  const double strain = accelerations(model, state.x, state.v, state.inv_mass, ws.a);  // a_n
  ws.x1.noalias() = state.x + half * state.v;                    // the half-step state
  ws.v1.noalias() = state.v + half * ws.a;
  accelerations(model, ws.x1, ws.v1, state.inv_mass, ws.a1);     // a_half
  state.x.noalias() += h * ws.v1;
  state.v.noalias() += h * ws.a1;
  StepStats stats;
  stats.force_evals = 2;
  stats.start_strain = strain;
  return stats;
}

}  // namespace clothsim
