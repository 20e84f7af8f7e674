// Backward Euler on the whole state: v_{n+1} = v_n + h a(x_{n+1}, v_{n+1}), x_{n+1} = x_n + h v_{n+1}.
// docs/integrators.md derives it; what a reader changing this file needs:
//
// solver: newton (default) minimises step_potential.h's Phi(dv), whose gradient is the residual
//     r(dv) = M dv - h f(x_n + h (v_n + dv), v_n + dv)
// (each damper's rate taken over the step, Gast et al. 2015). Directions by PCG truncated at
// negative curvature (Nocedal & Wright, Alg. 7.1), preconditioned by block Jacobi or a sparse
// factor chosen by counted work; an Armijo line search on Phi; contacts held as an active set
// by filtering (step_contacts.h), or under collision.model: barrier terms of Phi, their Hessian
// projected to PSD, the line search never letting a distance reach zero (barrier_terms.h).
// First guess: first_guess.h; matrix reuse: newton_solve.h.
// Converged when |S r| <= newton_tolerance max(|h f(x_n)|, |M dv|) (floored at f's rounding).
// NewtonMode::BaraffWitkin (model_params.h) is Baraff & Witkin 1998's step instead: one
// system linearised at y = x_n on the projected Hessian, taken whole.
//
// solver: fixed_point: K iterations y <- y_n + h F(y) from the forward-Euler predictor, the
// seed's instantaneous damper rate. K = 1 is the course's "implicit": amplification 1 + z + z^2,
// stable on the oscillator only for w h <= 1. StepStats then counts force_evals = 1 + K and
// newton_iterations = K; residual = |v_K - v_{K-1}| / |v_K - v_n|.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "integrator.h"
#include "core/model/forces.h"
#include "core/model/barrier_contacts.h"
#include "core/implicit/barrier_terms.h"
#include "core/implicit/first_guess.h"
#include "core/implicit/implicit_cache.h"
#include "core/implicit/newton_kernels.h"
#include "core/implicit/newton_solve.h"
#include "core/implicit/step_contacts.h"
#include "core/implicit/step_potential.h"

namespace clothsim {

namespace {

// Active-set rounds (let go / take in) after the first solve of a step.
constexpr int kMaxContactRounds = 4;

// |h f| at the iterate: M dv - r over movable bodies (mass[i] = 1 / w_i, 0 where w_i = 0).
double impulse_norm(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& dv, const Eigen::Matrix3Xd& r) {
  return std::sqrt(simd_impulse_norm2(mass.data(), dv.data(), r.data(), static_cast<std::size_t>(dv.cols())));
}

// The trace's line at a step's start: how the predicted held set differs from the last step's,
// which first guess was taken, and how far the start iterate's particles lie from the recorded
// Newton matrix's linearisation point (largest, m; -1: none recorded).
void trace_step_start(const NewtonTracer& trace, const Model& model, const State& state,
                      const ImplicitCache& c, const char* guess) {
  std::vector<char> before(model.num_bodies(), 0), now(model.num_bodies(), 0);
  for (int b : state.implicit.held) before[b] = 1;
  for (int b : c.contacts.filter.body) now[b] = 1;
  int added = 0, dropped = 0;
  for (int b = 0; b < model.num_bodies(); ++b) {
    added += now[b] && !before[b];
    dropped += before[b] && !now[b];
  }
  const Eigen::Index P = model.num_particles;
  const Eigen::Matrix3Xd& lin_y = state.implicit.lin.y;
  const double far = lin_y.cols() != model.num_bodies() || P == 0 ? -1.0
      : (c.y.leftCols(P) - lin_y.leftCols(P)).colwise().norm().maxCoeff();
  trace("newton step %lld start: held +%d -%d, guess %s, from the matrix's point %.3e m\n",
        static_cast<long long>(state.step), added, dropped, guess, far);
}

// Spring lengths l_n at the step's start (and so its start strain): from the last step's end
// where the state starts exactly there (the same lengths, bit for bit, without the pass).
double start_lengths(const Model& model, const State& state, ImplicitCache& c) {
  const int B = model.num_bodies();
  const bool ended_here = !c.y_length.empty() && c.y.cols() == B &&
                          std::memcmp(c.y.data(), state.x.data(), sizeof(double) * 3 * B) == 0;
  double strain = 0.0;
  if (ended_here) {
    c.start_length.swap(c.y_length);
    strain = step_strain(model, c.start_length);
  } else {
    strain = step_lengths(model, state.x, c.start_length);
  }
  c.y_length.clear();  // describes no y until the next evaluation
  return strain;
}

// 1 / w and 1 / w^2 per body, formed again only when the inverse masses changed.
void update_masses(const Eigen::VectorXd& w, ImplicitCache& c) {
  if (c.mass_of.size() == w.size() && c.mass_of == w) return;
  const Eigen::Index B = w.size();
  c.mass_of = w;
  c.mass.resize(B);
  c.mass_squared.resize(B);
  for (Eigen::Index i = 0; i < B; ++i) {
    c.mass[i] = w[i] != 0.0 ? 1.0 / w[i] : 0.0;
    c.mass_squared[i] = w[i] != 0.0 ? 1.0 / (w[i] * w[i]) : 0.0;
  }
}

// Zeroes the columns of immovable bodies.
void hold_immovable(const Eigen::VectorXd& w, Eigen::Matrix3Xd& m) {
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (w[i] == 0.0) m.col(i).setZero();
}

// The step's first guess: the last step's dv, or the line or parabola through the last steps'
// dv where that predicted the last step better (first_guess.h); null before any step.
// Baraff & Witkin's step takes the last dv as CG's warm start, as it always did.
struct FirstGuess {
  const Eigen::Matrix3Xd* dv = nullptr;
  int order = 0;
  const char* name() const { return !dv ? "none" : order == 2 ? "parabola" : order == 1 ? "line" : "last dv"; }
};
FirstGuess first_guess(const DvHistory& past, const State& state, NewtonMode mode, ImplicitCache& c) {
  FirstGuess g;
  if (past.count == 0) return g;
  g.order = mode == NewtonMode::BaraffWitkin ? 0 : std::min(state.implicit.guess_order, past.count - 1);
  if (g.order > 0) guess_through(past, g.order, c.guess);
  g.dv = g.order > 0 ? &c.guess : &state.implicit.dv;
  return g;
}

// What the residual is measured against: the step's impulse |h f| at the start, floored where
// f is only known to rounding (a spring force is a difference of terms of size ks l0): below
// 64 eps h |ks l0| no iteration can reduce |r|, and a state at rest must not read unconverged.
double residual_scale(const ImplicitDef& cfg, double h, const ImplicitCache& c) {
  constexpr double kRoundingFactor = 64.0 * std::numeric_limits<double>::epsilon();
  const double scale_floor = kRoundingFactor * h * c.force_scale / cfg.newton_tolerance;
  return std::max(impulse_norm(c.mass, c.dv, c.r), scale_floor);
}

// Newton on the first active set, then rounds that let go of pulling contacts, take in
// penetrating particles and resume. Returns whether the last solve converged.
bool solve_step(NewtonSolve& newton, const State& state, double h, NewtonMode mode,
                const Eigen::Matrix3Xd* warm, ImplicitCache& c, const NewtonTracer& trace) {
  bool converged = newton.iterate(warm);
  const int rounds = mode == NewtonMode::BaraffWitkin ? 0 : kMaxContactRounds;
  for (int round = 0; round < rounds; ++round) {
    if (!newton.update_contacts()) break;
    trace("  active-set round %d: held %zu\n", round, c.contacts.size());
    place_on_planes(c.contacts, state, h, c.dv);
    newton.evaluate();
    converged = newton.iterate(nullptr);
  }
  return converged;
}

// v_{n+1} = v_n + dv, x_{n+1} = x_n + h v_{n+1}; the contact response; the solver's history.
void finish_step(const Model& model, const DvHistory& past, NewtonMode mode, double h,
                 ImplicitCache& c, State& state) {
  simd_finish_step(state.x.data(), state.v.data(), c.dv.data(), h, static_cast<std::size_t>(c.dv.size()));
  respond_to_step_contacts(model, c.contacts, c.r, state);
  ImplicitSolverState& s = state.implicit;
  // Which guess the solution lay closest to decides the next step's.
  s.guess_order = mode == NewtonMode::BaraffWitkin ? 0 : next_guess_order(past, c.dv);
  s.dv_before2.swap(s.dv_before);
  s.dv_before.swap(s.dv);
  s.dv = c.dv;
  s.held = c.contacts.filter.body;
}

StepStats newton_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  const ImplicitDef& cfg = model.implicit;
  ImplicitCache& c = cache_for(model, ws);
  const NewtonTracer trace(ws);
  const Eigen::VectorXd& w = state.inv_mass;
  const NewtonMode mode = cfg.newton_mode();
  StepStats stats;
  stats.start_strain = start_lengths(model, state, c);
  const DvHistory past(state, model.num_bodies());
  const FirstGuess guess = first_guess(past, state, mode, c);
  predict_step_contacts(model, state, h, guess.dv, c.contacts);
  update_masses(w, c);

  // A full solve starts from the guess; Baraff & Witkin's step at y = x_n (dv = -v_n) and
  // takes the guess as CG's warm start. Either way held particles start on their planes.
  if (guess.dv && mode == NewtonMode::Converged) c.dv = *guess.dv;
  else c.dv = -state.v;
  hold_immovable(w, c.dv);
  place_on_planes(c.contacts, state, h, c.dv);
  if (uses_barrier(model)) barrier_feasible_start(model, state, h, c.dv);  // Phi finite at the start
  NewtonSolve newton(model, state, h, c, stats, trace);
  newton.evaluate();
  if (trace.on()) trace_step_start(trace, model, state, c, guess.name());
  newton.set_scale(residual_scale(cfg, h, c));
  const Eigen::Matrix3Xd* warm = nullptr;
  if (guess.dv && mode == NewtonMode::BaraffWitkin) {
    c.d = *guess.dv - c.dv;
    hold_immovable(w, c.d);
    warm = &c.d;
  }
  stats.converged = solve_step(newton, state, h, mode, warm, c, trace);
  stats.contact_constraints = static_cast<int>(c.contacts.size());
  state.implicit.factored = newton.factored();
  state.implicit.jacobi_solve = newton.jacobi_solve();
  if (mode == NewtonMode::Converged) state.implicit.lin_trusted = newton.trusted();
  finish_step(model, past, mode, h, c, state);
  return stats;
}

StepStats fixed_point_step(const Model& model, State& state, double h, Workspace& ws) {
  const int K = model.implicit.fixed_point_iterations;
  const Eigen::VectorXd& w = state.inv_mass;
  StepStats stats;

  // Predictor: forward Euler, y^0 = y_n + h F(y_n), held in (x1, v1).
  stats.start_strain = accelerations(model, state.x, state.v, w, ws.a);
  ++stats.force_evals;
  ws.x1.noalias() = state.x + h * state.v;
  ws.v1.noalias() = state.v + h * ws.a;
  for (int k = 0; k < K; ++k) {
    // y^{k+1} = y_n + h F(y^k), written into (x2, v2) then swapped in (no copy, no allocation).
    accelerations(model, ws.x1, ws.v1, w, ws.a1);
    ++stats.force_evals;
    ws.x2.noalias() = state.x + h * ws.v1;
    ws.v2.noalias() = state.v + h * ws.a1;
    ws.x1.swap(ws.x2);
    ws.v1.swap(ws.v2);
  }
  stats.newton_iterations = K;
  if (K > 0) {  // v2 now holds the previous iterate
    const double moved = (ws.v1 - state.v).norm();
    const double last = (ws.v1 - ws.v2).norm();
    stats.residual = last == 0.0 ? 0.0 : last / moved;
  }
  state.x.swap(ws.x1);
  state.v.swap(ws.v1);
  return stats;
}

}  // namespace

double implicit_reuse_reach(const Model& model, double h) {
  double shortest = std::numeric_limits<double>::infinity();
  for (double rest : model.springs.rest) shortest = std::min(shortest, rest);
  return reuse_reach(shortest, analysis::estimate_stiffness(model), h);
}

StepStats implicit_euler_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  switch (model.implicit.solver) {
    case ImplicitSolver::Newton: return newton_step(model, state, ctx, ws);
    case ImplicitSolver::FixedPoint: return fixed_point_step(model, state, ctx.h, ws);
  }
  return newton_step(model, state, ctx, ws);
}

}  // namespace clothsim
