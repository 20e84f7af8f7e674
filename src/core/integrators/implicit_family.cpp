// The implicit family's shared machinery and its Newmark-type methods (implicit_family.h).
#include "implicit_family.h"

#include <cmath>
#include <utility>

#include "core/model/forces.h"
#include "core/implicit/incremental_step.h"
#include "core/implicit/step_contacts.h"

namespace clothsim {

NewmarkDef newmark_params(const MethodSettings& settings) { return settings.methods.newmark; }
GeneralizedAlphaDef generalized_alpha_params(const MethodSettings& settings) {
  return settings.methods.generalized_alpha;
}

AlphaMethod newmark_method(const NewmarkDef& p) { return {0.0, 0.0, p.beta, p.gamma}; }

AlphaMethod generalized_alpha_method(const GeneralizedAlphaDef& p) {
  const double rho = p.rho_inf;
  AlphaMethod m;
  m.am = (2.0 * rho - 1.0) / (rho + 1.0);
  m.af = rho / (rho + 1.0);
  m.gamma = 0.5 - m.am + m.af;
  m.beta = 0.25 * (1.0 - m.am + m.af) * (1.0 - m.am + m.af);
  return m;
}

void family_solve(const Model& model, const ImplicitDef& cfg, State& state, Eigen::Matrix3Xd& xs,
                  Eigen::Matrix3Xd& vs, const StepForm& form, ImplicitCache& c, const NewtonTracer& trace,
                  StepStats& stats) {
  State start;  // the pseudo-start, with the step's inverse masses and the solver's memory
  start.x.swap(xs);
  start.v.swap(vs);
  start.inv_mass.swap(state.inv_mass);
  std::swap(start.implicit, state.implicit);
  start.t = state.t;
  start.step = state.step;
  solve_incremental(model, cfg, start, form, c, trace, stats);
  start.x.swap(xs);
  start.v.swap(vs);
  start.inv_mass.swap(state.inv_mass);
  std::swap(start.implicit, state.implicit);
}

void respond_to_family_contacts(const Model& model, double impulse, ImplicitCache& c, State& state) {
  if (c.contacts.size() == 0) return;
  c.r *= impulse;  // (scratch: the next evaluation writes it again)
  respond_to_step_contacts(model, c.contacts, c.r, state);
}

void move_immovable(const Eigen::Matrix3Xd& x_n, const Eigen::Matrix3Xd& v_n, double h, State& state) {
  for (Eigen::Index i = 0; i < state.inv_mass.size(); ++i) {
    if (state.inv_mass[i] != 0.0) continue;
    state.x.col(i) = x_n.col(i) + h * v_n.col(i);
    state.v.col(i) = v_n.col(i);
  }
}

void shift_reference_lengths(const Model& model, const State& state, const Eigen::Matrix3Xd* a, double A,
                             double Bh, double damper_h, std::vector<double>& length) {
  const Springs& springs = model.springs;
  const bool by_slot = model.spring_path() != SpringPath::List;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = springs.a[s], j = springs.b[s];
    const Vec3 d = state.x.col(i) - state.x.col(j);
    const double l = d.norm();
    if (!(l > 0.0)) continue;  // no direction: the rate's offset is undefined (and the force zero)
    const Vec3 u = d / l;
    const Vec3 dv = state.v.col(i) - state.v.col(j);
    const double rate = u.dot(dv);
    double q = A * rate;
    if (Bh != 0.0) {  // the length's second derivative: u . (a_a - a_b) + |dv transverse|^2 / l
      const double second = u.dot(a->col(i) - a->col(j)) + (dv - rate * u).squaredNorm() / l;
      q += Bh * second;
    }
    length[by_slot ? model.spring_layout.slot[s] : s] -= damper_h * q;
  }
}

StepStats alpha_method_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws,
                            IntegratorKind kind, const AlphaMethod& m) {
  const double h = ctx.h;
  ImplicitCache& c = cache_for(model, ctx.settings.implicit, ws);
  const NewtonTracer trace(ws);
  StepStats stats;
  StepHistory& hist = state.history;
  if (!hist.continues(kind, state)) {  // a_n from the current forces
    accelerations(model, state.x, state.v, state.inv_mass, hist.a);
    ++stats.force_evals;
  }
  const Eigen::Matrix3Xd& a_n = hist.a;
  stats.start_strain = start_lengths(model, state, c);

  // The stage y = x_{n+1-af} = x_hat + c h^2 a_m, a_m = (1 - am) a_{n+1} + am a_n (implicit_family.h).
  const double cf = (1.0 - m.af) * m.beta / (1.0 - m.am);
  const double he = h * std::sqrt(cf);
  const double damper_h = m.beta * h / m.gamma;
  const double A = 1.0 - (1.0 - m.af) * m.gamma / m.beta;
  const double Bh = (1.0 - m.af) * h * (1.0 - m.gamma / (2.0 * m.beta));
  const double hat_a = (1.0 - m.af) * h * h * ((0.5 - m.beta) - m.beta * m.am / (1.0 - m.am));
  shift_reference_lengths(model, state, &a_n, A, Bh, damper_h, c.start_length);
  // Pseudo-start: x_s = x_n - damper_h v_offset (so v(y) = (y - x_s) / damper_h), v_s = (x_hat - x_s) / h_e.
  ws.x1.noalias() = state.x - damper_h * (A * state.v + Bh * a_n);
  ws.v1.noalias() = (state.x + ((1.0 - m.af) * h) * state.v + hat_a * a_n - ws.x1) / he;
  StepForm form(he, damper_h, he * he / damper_h);
  form.lag_x = &state.x;
  form.contact_stage = 1.0 - m.af;  // the barrier at x_{n+1} = x_n + (y - x_n) / (1 - af)
  family_solve(model, ctx.settings.implicit, state, ws.x1, ws.v1, form, c, trace, stats);

  // a_{n+1} = (a_m - am a_n) / (1 - am), a_m = dv / h_e; then Newmark's updates.
  ws.a1.noalias() = (c.dv / he - m.am * a_n) / (1.0 - m.am);
  ws.x2 = state.x;
  ws.v2 = state.v;
  state.x.noalias() = ws.x2 + h * ws.v2 + (h * h) * ((0.5 - m.beta) * a_n + m.beta * ws.a1);
  state.v.noalias() = ws.v2 + h * ((1.0 - m.gamma) * a_n + m.gamma * ws.a1);
  move_immovable(ws.x2, ws.v2, h, state);
  respond_to_family_contacts(model, h * m.gamma / ((1.0 - m.am) * he), c, state);
  hist.a.swap(ws.a1);
  if (c.contacts.size() == 0) hist.record(kind, state);
  else hist.filled = false;  // a projection contact: the next step re-initialises a_n
  return stats;
}

}  // namespace clothsim
