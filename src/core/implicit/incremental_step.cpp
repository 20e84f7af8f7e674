// The implicit family's Newton solve of one step (incremental_step.h).
#include "incremental_step.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "barrier_terms.h"
#include "first_guess.h"
#include "newton_kernels.h"
#include "newton_solve.h"
#include "step_contacts.h"
#include "step_potential.h"
#include "core/model/barrier_contacts.h"

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

// The solver's history: which guess the solution lay closest to decides the next step's, the
// last three dv, and the held set.
void record_solver_history(const DvHistory& past, NewtonMode mode, const ImplicitCache& c, ImplicitSolverState& s) {
  s.guess_order = mode == NewtonMode::BaraffWitkin ? 0 : next_guess_order(past, c.dv);
  s.dv_before2.swap(s.dv_before);
  s.dv_before.swap(s.dv);
  s.dv = c.dv;
  s.held = c.contacts.filter.body;
}

}  // namespace

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

void solve_incremental(const Model& model, const ImplicitDef& cfg, State& start, const StepForm& form,
                       ImplicitCache& c, const NewtonTracer& trace, StepStats& stats) {
  const double h = form.h;
  const Eigen::VectorXd& w = start.inv_mass;
  const NewtonMode mode = cfg.newton_mode();
  const DvHistory past(start, model.num_bodies());
  const FirstGuess guess = first_guess(past, start, mode, c);
  predict_step_contacts(model, start, h, guess.dv, c.contacts);
  update_masses(w, c);

  // A full solve starts from the guess; Baraff & Witkin's step at y = x_s (dv = -v_s) and
  // takes the guess as CG's warm start. Either way held particles start on their planes.
  if (guess.dv && mode == NewtonMode::Converged) c.dv = *guess.dv;
  else c.dv = -start.v;
  hold_immovable(w, c.dv);
  place_on_planes(c.contacts, start, h, c.dv);
  if (uses_barrier(model)) barrier_feasible_start(model, start, form, c.dv);  // Phi finite at the start
  NewtonSolve newton(model, cfg, start, form, c, stats, trace);
  newton.evaluate();
  if (trace.on()) trace_step_start(trace, model, start, c, guess.name());
  newton.set_scale(residual_scale(cfg, h, c));
  const Eigen::Matrix3Xd* warm = nullptr;
  if (guess.dv && mode == NewtonMode::BaraffWitkin) {
    c.d = *guess.dv - c.dv;
    hold_immovable(w, c.d);
    warm = &c.d;
  }
  stats.converged = solve_step(newton, start, h, mode, warm, c, trace);
  stats.contact_constraints = static_cast<int>(c.contacts.size());
  start.implicit.factored = newton.factored();
  start.implicit.jacobi_solve = newton.jacobi_solve();
  if (mode == NewtonMode::Converged) start.implicit.lin_trusted = newton.trusted();
  record_solver_history(past, mode, c, start.implicit);
}

}  // namespace clothsim
