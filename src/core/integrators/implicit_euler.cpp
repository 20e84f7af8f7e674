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
// First guess: first_guess.h; matrix reuse: newton_solve.h; the solve: incremental_step.h.
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
#include "core/implicit/implicit_cache.h"
#include "core/implicit/incremental_step.h"
#include "core/implicit/newton_kernels.h"
#include "core/implicit/newton_solve.h"
#include "core/implicit/step_contacts.h"

namespace clothsim {

namespace {

StepStats newton_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  ImplicitCache& c = cache_for(model, ctx.settings.implicit, ws);
  const NewtonTracer trace(ws);
  StepStats stats;
  stats.start_strain = start_lengths(model, state, c);  // l_n: the dampers' reference lengths
  solve_incremental(model, ctx.settings.implicit, state, ctx.h, c, trace, stats);
  // v_{n+1} = v_n + dv, x_{n+1} = x_n + h v_{n+1}; the contact response on the held particles.
  simd_finish_step(state.x.data(), state.v.data(), c.dv.data(), ctx.h, static_cast<std::size_t>(c.dv.size()));
  respond_to_step_contacts(model, c.contacts, c.r, state);
  return stats;
}

StepStats fixed_point_step(const Model& model, State& state, double h, int K, Workspace& ws) {
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
  const ImplicitDef& cfg = ctx.settings.implicit;
  switch (cfg.solver) {
    case ImplicitSolver::Newton: return newton_step(model, state, ctx, ws);
    case ImplicitSolver::FixedPoint: return fixed_point_step(model, state, ctx.h, cfg.fixed_point_iterations, ws);
  }
  return newton_step(model, state, ctx, ws);
}

}  // namespace clothsim
