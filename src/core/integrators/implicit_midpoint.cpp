// The implicit midpoint rule on (x, v):
//     x_{n+1} = x_n + h v_m,   v_{n+1} = v_n + h a(x_m, v_m),   x_m = (x_n + x_{n+1})/2, v_m = (v_n + v_{n+1})/2,
// symplectic, order 2, and on a linear spring it keeps the energy exactly (a quadratic
// invariant), |R(i w h)| = 1 at every step. Its stage is a backward Euler step of h/2 from
// (x_n, v_n) to (x_m, v_m) (c = 1/4, the dampers at (l - l_n) / (h/2)), then the forward half
// x_{n+1} = 2 x_m - x_n, v_{n+1} = 2 v_m - v_n (implicit_family.h): one-step, no history.
#include "implicit_family.h"

#include "core/implicit/incremental_step.h"

namespace clothsim {

StepStats implicit_midpoint_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  ImplicitCache& c = cache_for(model, ctx.settings.implicit, ws);
  const NewtonTracer trace(ws);
  StepStats stats;
  stats.start_strain = start_lengths(model, state, c);  // l_n: the half step's reference lengths
  StepForm half(0.5 * h);
  half.contact_stage = 0.5;  // the barrier at x_{n+1} = 2 x_m - x_n (implicit_family.h)
  solve_incremental(model, ctx.settings.implicit, state, half, c, trace, stats);  // v_m = v_n + dv, x_m = x_n + h/2 v_m
  state.x.noalias() += h * (state.v + c.dv);  // x_n + h v_m (immovable bodies: dv = 0)
  state.v.noalias() += 2.0 * c.dv;            // 2 v_m - v_n
  respond_to_family_contacts(model, 2.0, c, state);
  return stats;
}

}  // namespace clothsim
