// ROS2 (Verwer, Spee, Blom and Hundsdorfer 1999), the two-stage Rosenbrock method, on
// y = (x, v), y' = F(y) = (v, M^-1 f(x, v)), with one matrix W = I - gamma h J a step:
//     W k1 = F(y_n),   W k2 = F(y_n + h k1) - 2 k1,   y_{n+1} = y_n + 3/2 h k1 + 1/2 h k2,
// gamma = 1 + 1/sqrt(2): L-stable (R(z) = (1 + (1 - 2 gamma) z) / (1 - gamma z)^2 -> 0 as
// |z| grows), and order 2 for any J (a W-method), so J may be the Newton matrix implicit_euler
// assembles. Its first stage with gamma = 1, taken whole, is Baraff & Witkin's step
// (implicit_euler:1). With J = [0 I; M^-1 K  M^-1 D] a stage's W k = (p, q) is, for k = (kx, kv),
//     (M - gamma h D - (gamma h)^2 K) kv = M q + gamma h K p,   kx = p + gamma h kv:
// the matrix is backward Euler's projected Hessian H of step gamma h at y = x_n (the dampers'
// reference lengths l_n: K the springs' stiffness, D the dampers' and drag's -kd u u^T and
// -c I; sparse_system.h), and K p is read back from H itself, K p = (M p - gamma h D p - H p) /
// (gamma h)^2, so both stages see one J whatever H's projection did. Two force passes and two
// block-Jacobi PCG solves a step. Contacts: the post-step projection (collision.model:
// projection) only: a linearly implicit step has no line search to keep the barrier's
// distances positive, so the barrier is refused (its registry row).
#include <cmath>

#include "integrator.h"
#include "core/model/forces.h"
#include "core/implicit/implicit_cache.h"
#include "core/implicit/incremental_step.h"
#include "core/implicit/sparse_system.h"

namespace clothsim {

namespace {

constexpr double kGamma = 1.0 + 0.70710678118654752;  // 1 + 1/sqrt(2)
constexpr double kCgTolerance = 1e-10;                 // relative: the stages' solves, near exact

// out = D p: the dampers' -kd (u . (p_a - p_b)) u at a (minus it at b), u at x, and the air
// drag's -c p on cloth particles; zero on immovable bodies.
void apply_damping(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::VectorXd& w,
                   const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& out) {
  out.setZero(3, p.cols());
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int a = s.a[k], b = s.b[k];
    const Vec3 d = x.col(a) - x.col(b);
    const double l = d.norm();
    if (!(l > 0.0) || s.kd[k] == 0.0) continue;
    const Vec3 u = d / l;
    const Vec3 f = (-s.kd[k] * u.dot(p.col(a) - p.col(b))) * u;
    out.col(a) += f;
    out.col(b) -= f;
  }
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (i < model.num_particles) out.col(i) -= model.air_drag * p.col(i);
    if (w[i] == 0.0) out.col(i).setZero();
  }
}

struct Stage {
  const Model& model;
  const State& state;
  ImplicitCache& c;
  Workspace& ws;
  double gh;  // gamma h
  StepStats& stats;

  // kv, kx for W k = (p, q): H kv = M q + gamma h K p, kx = p + gamma h kv.
  void solve(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& kx, Eigen::Matrix3Xd& kv) {
    const Eigen::VectorXd& w = state.inv_mass;
    Eigen::Matrix3Xd& Hp = c.r;   // scratch (the Newton solve's, unused here)
    Eigen::Matrix3Xd& Dp = c.d;
    Eigen::Matrix3Xd& b = c.rhs;
    Hp.resize(3, p.cols());
    multiply(c.A, p, Hp);
    apply_damping(model, state.x, w, p, Dp);
    b.resize(3, p.cols());
    for (Eigen::Index i = 0; i < p.cols(); ++i) {
      if (w[i] == 0.0) {
        b.col(i).setZero();
        continue;
      }
      const double m = 1.0 / w[i];
      // M q + gamma h K p, with gamma h K p = (M p - gamma h D p - H p) / (gamma h)
      b.col(i) = m * q.col(i) + (m * p.col(i) - gh * Dp.col(i) - Hp.col(i)) / gh;
    }
    CgSettings settings;
    settings.tolerance = kCgTolerance;
    settings.max_iterations = 10 * static_cast<int>(p.cols()) + 100;
    kv.setZero(3, p.cols());
    const CgResult cg = solve_pcg(c.A, b, kv, settings, c.cg);
    stats.cg_iterations += cg.iterations;
    stats.converged = stats.converged && cg.converged;
    stats.residual = std::max(stats.residual, cg.relative_residual);
    kx.noalias() = p + gh * kv;
  }
};

}  // namespace

StepStats ros2_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h, gh = kGamma * h;
  ImplicitCache& c = cache_for(model, ctx.settings.implicit, ws);
  StepStats stats;
  stats.start_strain = start_lengths(model, state, c);  // l_n: no damper tension at y = x_n
  assemble_step_hessian(model, state.inv_mass, gh, c.start_length, state.x, HessianBlocks::Projected, c.A);
  ++stats.assemblies;
  c.holds_record = false;  // A is not a recorded Newton matrix
  c.y_length.clear();
  Stage stage{model, state, c, ws, gh, stats};

  // Stage 1: W k1 = F(y_n) = (v_n, a_n).
  accelerations(model, state.x, state.v, state.inv_mass, ws.a);
  stage.solve(state.v, ws.a, ws.x1, ws.v1);  // (kx1, kv1)
  // Stage 2: W k2 = F(y_n + h k1) - 2 k1.
  ws.x2.noalias() = state.x + h * ws.x1;
  ws.v2.noalias() = state.v + h * ws.v1;
  accelerations(model, ws.x2, ws.v2, state.inv_mass, ws.a1);
  ws.v2 -= 2.0 * ws.x1;  // p = v* - 2 kx1
  ws.a1 -= 2.0 * ws.v1;  // q = a* - 2 kv1
  stage.solve(ws.v2, ws.a1, ws.x2, ws.a);  // (kx2, kv2)
  stats.force_evals = 2;
  state.x += h * (1.5 * ws.x1 + 0.5 * ws.x2);
  state.v += h * (1.5 * ws.v1 + 0.5 * ws.a);
  return stats;
}

}  // namespace clothsim
