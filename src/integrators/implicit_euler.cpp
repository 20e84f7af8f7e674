// Backward (implicit) Euler on the whole state:
//     v_{n+1} = v_n + h a(x_{n+1}, v_{n+1}),   x_{n+1} = x_n + h v_{n+1}.
// First order and unconditionally stable: for x'' = -w^2 x its amplification 1 / (1 - z),
// z = i w h, has modulus 1 / sqrt(1 + (w h)^2) < 1, so it loses energy at every step size.
// Writing v_{n+1} = v_n + dv, the step is the root of the residual
//     r(dv) = M dv - h f(x_n + h (v_n + dv), v_n + dv).
//
// solver: newton (default). Newton's method on r with the spring Jacobians, each linear
// system A ddv = -r, A = M - h df/dv - h^2 df/dx, solved by block-Jacobi PCG in the fixed
// pattern of sparse_system.h (the symmetric stiffness part of df/dx; for compressed springs
// exact first, clamped if CG fails on it: see solve_newton_system).
// The first iterate is Baraff & Witkin 1998's step (eq. 16): linearised about (x_n, v_n),
//     A dv = h (f_n + h (df/dx) v_n), the matrix approximated (below), (df/dx) v_n exact.
// Every iterate is then judged by the true nonlinear residual |r(dv)|, relative to
// max(|h f_n|, |M dv|) over movable bodies (floored at the rounding level of f: see
// newton_step); below newton_tolerance backward Euler is solved. Until then each further
// iterate is a Newton correction with A rebuilt at the current guess.
// Because A is only the symmetric part of the Jacobian this is an inexact Newton method:
// convergence is linear rather than quadratic when dampers are strong, but the residual
// test keeps "converged" honest. newton_max_iterations = 1 is Baraff & Witkin's method.
//
// solver: fixed_point. K fixed-point iterations y <- y_n + h F(y) on the whole state
// y = (x, v), from the forward-Euler predictor y = y_n + h F(y_n). Their fixed point is
// backward Euler, but the iteration only contracts when h |dF/dy| < 1: for the linear test
// equation K iterations give the amplification 1 + z + ... + z^{K+1}, so K = 1 (the course
// framework's "implicit" integrator) has 1 + z + z^2, which on the oscillator (z = i w h)
// is stable only for w h <= 1. It exists so users can see that difference.
//
// StepStats, newton:
//   force_evals        total_forces() calls: 1 at (x_n, v_n) + 1 residual check per iterate.
//   newton_iterations  linear solves, each preceded by one Jacobian assembly (1 = B & W).
//   cg_iterations      PCG iterations summed over those solves (each one block mat-vec).
//   residual           the final relative nonlinear residual (above).
//   converged          residual <= newton_tolerance. A CG solve that stops at its cap does
//                      not by itself fail the step: the next residual check decides.
// StepStats, fixed_point:
//   force_evals = 1 + K, newton_iterations = K, cg_iterations = 0,
//   residual = |v_K - v_{K-1}| / |v_K - v_n| (how far the last iteration still moved v),
//   converged = true: a fixed number of iterations, with no tolerance to miss.
#include <algorithm>
#include <cmath>
#include <limits>

#include "forces.h"
#include "integrator.h"
#include "integrators/conjugate_gradient.h"
#include "integrators/sparse_system.h"

namespace clothsim {

// The sparse pattern and the buffers the Newton solve needs, built once per model (the
// Workspace belongs to one run, so to one model) and resized only if the body count changes.
struct ImplicitCache {
  const Model* model = nullptr;
  double force_scale = 0.0;  // N, sqrt(sum_s (ks_s l0_s)^2): the size of the spring forces' terms
  SpringBlockMatrix A;
  Eigen::Matrix3Xd rhs, ddv, Jv, residual;  // (3 x B)
  CgBuffers cg;
};

void ImplicitCacheDeleter::operator()(ImplicitCache* cache) const { delete cache; }

namespace {

ImplicitCache& cache_for(const Model& model, Workspace& ws) {
  if (!ws.implicit) ws.implicit.reset(new ImplicitCache);
  ImplicitCache& c = *ws.implicit;
  if (c.model != &model || c.A.num_bodies() != model.num_bodies() ||
      c.A.off.size() != model.springs.size()) {
    build_pattern(model, c.A);
    c.model = &model;
    double sum = 0.0;
    for (std::size_t s = 0; s < model.springs.size(); ++s)
      sum += std::pow(model.springs.ks[s] * model.springs.rest[s], 2);
    c.force_scale = std::sqrt(sum);
  }
  return c;
}

// r = M dv - h f over movable bodies (f is zero on immovable ones and dv stays zero there).
void nonlinear_residual(const Eigen::VectorXd& inv_mass, const Eigen::Matrix3Xd& dv,
                        const Eigen::Matrix3Xd& f, double h, Eigen::Matrix3Xd& r) {
  const int B = static_cast<int>(inv_mass.size());
  r.resize(3, B);
  for (int i = 0; i < B; ++i) {
    if (inv_mass[i] == 0.0) {
      r.col(i).setZero();
    } else {
      r.col(i).noalias() = dv.col(i) / inv_mass[i] - h * f.col(i);
    }
  }
}

double momentum_norm(const Eigen::VectorXd& inv_mass, const Eigen::Matrix3Xd& dv) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < inv_mass.size(); ++i) {
    if (inv_mass[i] != 0.0) sum += dv.col(i).squaredNorm() / (inv_mass[i] * inv_mass[i]);
  }
  return std::sqrt(sum);
}

// One linear solve of a Newton iteration at (x, v): A ddv = rhs, with rhs = h (f_n + h (df/dx) v)
// for Baraff & Witkin's first iterate (f_n in `first_force`) or -r for a correction.
// The exact stiffness is tried first: it is the true Jacobian, so Newton converges fastest
// with it, and CG succeeds whenever A stays positive definite, as it does unless springs
// are compressed hard at a large step. If CG breaks down (non-positive curvature) or misses
// its tolerance, A is rebuilt with compression clamped, which is positive definite by
// construction (sparse_system.h), and the solve repeated from zero.
// `accuracy` is the absolute residual (momentum, kg m/s) the Newton test can resolve: CG
// stops there even above cg_tolerance, since solving the linearisation more finely than the
// nonlinear equations are judged buys nothing (an inexact Newton method's forcing term).
// `from_guess` starts CG from `solution` as passed in (the previous step's dv).
void solve_newton_system(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                         const Eigen::VectorXd& w, double h, const Eigen::Matrix3Xd* first_force,
                         double accuracy, bool from_guess, ImplicitCache& c,
                         Eigen::Matrix3Xd& solution, StepStats& stats) {
  const ImplicitDef& cfg = model.implicit;
  CgSettings settings;
  settings.max_iterations = cfg.cg_max_iterations;
  settings.tolerance = cfg.cg_tolerance;
  settings.absolute_tolerance = accuracy;
  settings.from_guess = from_guess;
  for (const bool clamp : {false, true}) {
    assemble_backward_euler_matrix(model, x, v, w, h, clamp, c.A, c.Jv);
    if (first_force) {
      c.rhs.noalias() = h * (*first_force + h * c.Jv);
    } else {
      c.rhs.noalias() = -c.residual;
    }
    const CgResult cg = solve_pcg(c.A, c.rhs, solution, settings, c.cg);
    stats.cg_iterations += cg.iterations;
    if (cg.converged) return;
    settings.from_guess = false;  // the failed attempt's iterate is no guess to start from
  }
}

StepStats newton_step(const Model& model, State& state, double h, Workspace& ws) {
  const ImplicitDef& cfg = model.implicit;
  ImplicitCache& c = cache_for(model, ws);
  const Eigen::VectorXd& w = state.inv_mass;
  StepStats stats;

  total_forces(model, state.x, state.v, w, ws.a);  // f_n
  ++stats.force_evals;
  // What the residual is measured against: the step's impulse |h f_n| or momentum change
  // |M dv|, floored where f itself is only known to rounding (a spring force is the
  // difference of terms of size ks l0, so its rounding error is ~eps ks l0): below
  // 64 eps h |ks l0| no iteration can reduce |r|, and a state at rest must not read as
  // unconverged for it.
  constexpr double kRoundingFactor = 64.0 * std::numeric_limits<double>::epsilon();
  const double scale_floor = kRoundingFactor * h * c.force_scale / cfg.newton_tolerance;
  const double impulse_scale = std::max(h * ws.a.norm(), scale_floor);

  // What the linear solves must resolve: a tenth of what the Newton test accepts.
  const double accuracy = 0.1 * cfg.newton_tolerance * impulse_scale;

  // Baraff & Witkin's system at (x_n, v_n): A dv = h (f_n + h (df/dx) v_n), warm-started from the
  // previous step's dv (still in ws.dv): at the small steps explicit methods need, dv changes
  // little from step to step and CG starts most of the way there. Bodies immovable now get 0.
  const bool have_guess = ws.dv.cols() == model.num_bodies();
  if (have_guess)
    for (int i = 0; i < model.num_bodies(); ++i)
      if (w[i] == 0.0) ws.dv.col(i).setZero();
  solve_newton_system(model, state.x, state.v, w, h, &ws.a, accuracy, have_guess, c, ws.dv, stats);
  stats.newton_iterations = 1;

  while (true) {
    // The true residual at the current guess, with f at the end-of-step state it implies.
    ws.v1.noalias() = state.v + ws.dv;
    ws.x1.noalias() = state.x + h * ws.v1;
    total_forces(model, ws.x1, ws.v1, w, ws.a1);
    ++stats.force_evals;
    nonlinear_residual(w, ws.dv, ws.a1, h, c.residual);
    const double r_norm = c.residual.norm();
    const double scale = std::max(impulse_scale, momentum_norm(w, ws.dv));
    stats.residual = r_norm / scale;
    if (stats.residual <= cfg.newton_tolerance) break;
    if (stats.newton_iterations >= cfg.newton_max_iterations || !std::isfinite(stats.residual)) {
      stats.converged = false;
      break;
    }
    // Newton correction: A(x_1, v_1) ddv = -r.
    solve_newton_system(model, ws.x1, ws.v1, w, h, nullptr, accuracy, false, c, c.ddv, stats);
    ++stats.newton_iterations;
    ws.dv += c.ddv;
  }

  state.v += ws.dv;           // v_{n+1} = v_n + dv (dv = 0 for immovable bodies)
  state.x += h * state.v;     // x_{n+1} = x_n + h v_{n+1}
  return stats;
}

StepStats fixed_point_step(const Model& model, State& state, double h, Workspace& ws) {
  const int K = model.implicit.fixed_point_iterations;
  const Eigen::VectorXd& w = state.inv_mass;
  StepStats stats;

  // Predictor: forward Euler, y^0 = y_n + h F(y_n), held in (x1, v1).
  accelerations(model, state.x, state.v, w, ws.a);
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

StepStats implicit_euler_step(const Model& model, State& state, double h, Workspace& ws) {
  switch (model.implicit.solver) {
    case ImplicitSolver::Newton: return newton_step(model, state, h, ws);
    case ImplicitSolver::FixedPoint: return fixed_point_step(model, state, h, ws);
  }
  return newton_step(model, state, h, ws);
}

}  // namespace clothsim
