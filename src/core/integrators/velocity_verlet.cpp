// Velocity Verlet and the composition machinery yoshida4 shares (verlet.h gives the method,
// its predicted velocity for the dampers and its orders).
#include "verlet.h"

#include "core/model/forces.h"

namespace clothsim {

StepStats verlet_composition(const Model& model, State& state, const StepContext& ctx, Workspace& ws,
                             IntegratorKind kind, const double* weights, int n) {
  StepHistory& hist = state.history;
  Eigen::Matrix3Xd& a = hist.a;  // a_n on entry to each substep, a_{n+1} on leaving it
  StepStats stats;
  if (hist.continues(kind, state)) {
    stats.start_strain = hist.strain;
  } else {
    stats.start_strain = accelerations(model, state.x, state.v, state.inv_mass, a);
    stats.force_evals = 1;
  }
  double strain = stats.start_strain;
  for (int k = 0; k < n; ++k) {
    const double h = weights[k] * ctx.h, half = 0.5 * h;
    state.v += half * a;                          // kick: v_{1/2}
    state.x += h * state.v;                       // drift: x_{n+1}
    ws.v1.noalias() = state.v + half * a;         // v*, for the velocity-dependent forces
    strain = accelerations(model, state.x, ws.v1, state.inv_mass, a);  // a_{n+1}
    state.v += half * a;                          // kick: v_{n+1}
    ++stats.force_evals;
  }
  hist.strain = strain;
  hist.record(kind, state);
  return stats;
}

StepStats velocity_verlet_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  static constexpr double kOne[] = {1.0};
  return verlet_composition(model, state, ctx, ws, IntegratorKind::VelocityVerlet, kOne, 1);
}

namespace {
// One substep of size h on (u, u', a) with a = -w^2 u - c u' taken at the predicted velocity,
// as verlet_composition takes it, applied to each column of the row-major 3 x 3 m.
void verlet_substep(double h, double w, double c, double m[9]) {
  const double half = 0.5 * h;
  for (int col = 0; col < 3; ++col) {
    double u = m[col], v = m[3 + col], a = m[6 + col];
    v += half * a;
    u += h * v;
    a = -w * w * u - c * (v + half * a);
    v += half * a;
    m[col] = u, m[3 + col] = v, m[6 + col] = a;
  }
}

void identity(double m[9]) {
  for (int i = 0; i < 9; ++i) m[i] = i % 4 == 0 ? 1.0 : 0.0;
}
}  // namespace

void velocity_verlet_matrix(double h, double w, double c, double m[9]) {
  identity(m);
  verlet_substep(h, w, c, m);
}

void yoshida4_matrix(double h, double w, double c, double m[9]) {
  identity(m);
  for (const double weight : {kYoshidaW1, kYoshidaW0, kYoshidaW1}) verlet_substep(weight * h, w, c, m);
}

}  // namespace clothsim
