// Classic fourth-order Runge-Kutta on the whole state y = (x, v), y' = F(y) = (v, a(x, v)):
//     k1 = F(y_n),  k2 = F(y_n + h/2 k1),  k3 = F(y_n + h/2 k2),  k4 = F(y_n + h k3),
//     y_{n+1} = y_n + h/6 (k1 + 2 k2 + 2 k3 + k4).
// With stage s's state (x_s, v_s) the x-part of k_{s+1} is v_s and its v-part a_s = a(x_s, v_s):
//     x_1 = x_n + h/2 v_n,  v_1 = v_n + h/2 a_n      (a_1 there)
//     x_2 = x_n + h/2 v_1,  v_2 = v_n + h/2 a_1      (a_2)
//     x_3 = x_n + h   v_2,  v_3 = v_n + h   a_2      (a_3)
//     x_{n+1} = x_n + h/6 (v_n + 2 v_1 + 2 v_2 + v_3) = x_n + h v_n + h^2/6 (a_n + a_1 + a_2)
//     v_{n+1} = v_n + h/6 (a_n + 2 a_1 + 2 a_2 + a_3)
// Both weighted sums matter: the seed's fragment updates v with the last stage only and
// builds stage positions from full-step velocities, which drops it to first order.
// Substituting the stage velocities into the x sum (the second form above) means the v_s are
// not needed after their stage, so one (x_s, v_s) buffer pair serves all three stages and
// the final update reads six arrays, not ten: RK4 costs its four force evaluations and
// little more. For x'' = -w^2 x the amplification is 1 + z + z^2/2 + z^3/6 + z^4/24,
// z = i w h: slightly dissipative for w h < 2 sqrt(2) ~ 2.83 and growing beyond.
#include "integrator.h"
#include "core/model/forces.h"

namespace clothsim {

StepStats rk4_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  const double half = 0.5 * h;
  const Eigen::Matrix3Xd& x = state.x;
  const Eigen::Matrix3Xd& v = state.v;
  const Eigen::VectorXd& w = state.inv_mass;
  Eigen::Matrix3Xd& xs = ws.x1;  // the stage state, overwritten stage by stage
  Eigen::Matrix3Xd& vs = ws.v1;

  const double strain = accelerations(model, x, v, w, ws.a);  // a_n
  xs.noalias() = x + half * v;
  vs.noalias() = v + half * ws.a;
  accelerations(model, xs, vs, w, ws.a1);  // a_1
  xs.noalias() = x + half * vs;            // reads v_1 before it is replaced by v_2
  vs.noalias() = v + half * ws.a1;
  accelerations(model, xs, vs, w, ws.a2);  // a_2
  xs.noalias() = x + h * vs;
  vs.noalias() = v + h * ws.a2;
  accelerations(model, xs, vs, w, ws.a3);  // a_3

  // One fused pass over the 3B coordinates: x first, as it reads v_n.
  const double h2_6 = h * h / 6.0, h_6 = h / 6.0;
  double* px = state.x.data();
  double* pv = state.v.data();
  const double* a0 = ws.a.data();
  const double* a1 = ws.a1.data();
  const double* a2 = ws.a2.data();
  const double* a3 = ws.a3.data();
  const Eigen::Index n = state.x.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double s012 = a0[i] + a1[i] + a2[i];
    px[i] += h * pv[i] + h2_6 * s012;
    pv[i] += h_6 * (s012 + a1[i] + a2[i] + a3[i]);
  }
  StepStats stats;
  stats.force_evals = 4;
  stats.start_strain = strain;
  return stats;
}

}  // namespace clothsim
