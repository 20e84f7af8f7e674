// IMEX in Bridson, Marino and Fedkiw's form ("Simulation of clothing with folds and
// wrinkles", SCA 2003, sec. 7): the elastic forces explicit, the damping implicit. With
// f(x, v) = f_e(x) + D(x) v, f_e the springs' elastic forces, gravity and the barrier (and its
// smoothed friction, taken at each kick's start velocity), D(x) v the seed's dampers
// -kd (u . (v_a - v_b)) u and the air drag -c v, both linear in v at fixed x:
//     v_{1/2} = v_n + h/2 M^-1 f(x_n, v_{1/2})            implicit in the damping only
//     x_{n+1} = x_n + h v_{1/2}
//     v_{n+1} = v_{1/2} + h/2 M^-1 f(x_{n+1}, v_{n+1})    again
// Each half kick is one linear solve in velocity, (M - h/2 D(x)) dv = h/2 f(x, v_start), exact
// because the damping is linear in v: M plus h/2 kd u u^T per damper and h/2 c I, SPD, solved by
// block-Jacobi PCG on implicit_euler's block pattern (sparse_system.h). The second kick's
// solution gives a(x_{n+1}, v_{n+1}) = dv / (h/2) for free (the kick's own equation), so the next
// step's first kick reuses it (first same as last, as velocity Verlet's, State::history), and
// its matrix at x_{n+1} (the same h/2) while the Workspace still holds it: one force pass, one
// assembly and two solves a step, each from the guess dv = h/2 a (exact without dampers).
//
// Order: 1 with dampers, 2 without (then it is velocity Verlet). On pure damping v' = -c v the
// two backward-Euler half kicks multiply v by (1 + ch/2)^-2 = 1 - ch + 3/4 (ch)^2 + ..., against
// e^{-ch} = 1 - ch + 1/2 (ch)^2: an O(h^2) error a step (tests/core/integrators/imex_test.cpp
// reads 1.00 on the damped spring, 2.00 undamped).
// Stability on u'' + c u' + w^2 u = 0: with d = 1 / (1 + ch/2) the step matrix has det d^2 and
// trace 1 + d^2 - d (1 + d) (w h)^2 / 2, so (Jury) it is stable while
//     (w h)^2 < 4 (1 + d^2) / (d (1 + d)),
// w h < 2 undamped and larger with the dampers: the spring stiffness bounds the step, never
// the damper (the explicit methods' limits shrink as c grows).
// Contacts as the explicit family's: the post-step projection (collision.model: projection),
// or the barrier's force in f_e, explicit, so its stiffness bounds the step as a spring's does.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>

#include "integrator.h"
#include "core/model/forces.h"
#include "core/implicit/implicit_cache.h"
#include "core/implicit/sparse_system.h"

namespace clothsim {

namespace {

// Relative: the damping solve's error, 1e-8 of a kick, stays far below the method's own O(h).
constexpr double kDampingCgTolerance = 1e-8;

// A = M - k D(x) (3 x B blocks, k = h/2): a damper's block G = -k kd u u^T off the diagonal,
// k kd u u^T on each moving end's diagonal, k c I for the drag on cloth particles; the identity
// on an immovable body's row and no block coupling it (its rows filtered, sparse_system.h).
// The matrix is SPD, so the projected blocks the preconditioner reads are the same.
void assemble_damping(const Model& model, const Eigen::VectorXd& w, double k, const Eigen::Matrix3Xd& x,
                      SpringBlockMatrix& A) {
  for (int i = 0; i < model.num_bodies(); ++i) {
    const double drag = i < model.num_particles ? model.air_drag : 0.0;
    A.diag[i].setIdentity();
    if (w[i] != 0.0) A.diag[i] *= 1.0 / w[i] + k * drag;
  }
  const Springs& s = model.springs;
  for (std::size_t e = 0; e < s.size(); ++e) {
    const int a = s.a[e], b = s.b[e];
    const std::size_t slot = A.slot[e];
    const Vec3 d = x.col(a) - x.col(b);
    const double l = d.norm();
    const Vec3 u = l > 0.0 ? Vec3(d / l) : Vec3::Zero();  // no direction: the damper acts on nothing
    const double g = k * s.kd[e];
    // g u u^T by its six entries, added in place (no 3 x 3 temporary: the assembly's cost)
    const double xx = g * u.x() * u.x(), yy = g * u.y() * u.y(), zz = g * u.z() * u.z();
    const double xy = g * u.x() * u.y(), xz = g * u.x() * u.z(), yz = g * u.y() * u.z();
    for (const int i : {a, b}) {
      if (w[i] == 0.0) continue;
      Mat3& D = A.diag[i];
      D(0, 0) += xx, D(1, 1) += yy, D(2, 2) += zz;
      D(0, 1) += xy, D(1, 0) += xy, D(0, 2) += xz, D(2, 0) += xz, D(1, 2) += yz, D(2, 1) += yz;
    }
    const bool coupled = w[a] != 0.0 && w[b] != 0.0;
    A.ux[slot] = u.x(), A.uy[slot] = u.y(), A.uz[slot] = u.z();
    A.alpha[slot] = A.alpha_projected[slot] = coupled ? -g : 0.0;
    A.beta[slot] = A.beta_projected[slot] = 0.0;
  }
  A.diag_projected = A.diag;
  A.refresh_copies();
  invert_diagonal(A);
}

// One implicit-damping half kick at x from v (state.v): v += dv, (M - k D(x)) dv = k M a, a =
// a(x, v), from the guess dv = k a (exact without dampers). Reassembles the matrix unless
// `reuse`. Leaves dv in c.dv.
void half_kick(const Model& model, State& state, double k, const Eigen::Matrix3Xd& a, bool reuse, ImplicitCache& c,
               StepStats& stats) {
  const Eigen::VectorXd& w = state.inv_mass;
  if (!reuse) {
    assemble_damping(model, w, k, state.x, c.damping);
    ++stats.assemblies;
  }
  c.rhs.resize(3, a.cols());
  for (Eigen::Index i = 0; i < a.cols(); ++i)
    c.rhs.col(i) = w[i] == 0.0 ? Vec3::Zero() : Vec3((k / w[i]) * a.col(i));
  CgSettings settings;
  settings.tolerance = kDampingCgTolerance;
  settings.max_iterations = 10 * static_cast<int>(a.cols()) + 100;
  settings.from_guess = true;
  c.dv.noalias() = k * a;
  const CgResult cg = solve_pcg(c.damping, c.rhs, c.dv, settings, c.cg);
  stats.cg_iterations += cg.iterations;
  stats.converged = stats.converged && cg.converged;
  stats.residual = std::max(stats.residual, cg.relative_residual);
  state.v += c.dv;
}

// A mark no other assembly has had (imex_step: which matrix the cache holds).
std::uint64_t next_mark() {
  static std::atomic<std::uint64_t> last{0};
  return ++last;
}

}  // namespace

StepStats imex_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  constexpr IntegratorKind kKind = IntegratorKind::Imex;
  const double h = ctx.h, k = 0.5 * h;
  ImplicitCache& c = cache_for(model, ctx.settings.implicit, ws);
  if (c.damping.num_bodies() != model.num_bodies()) build_pattern(model, ctx.settings.implicit.single_from, c.damping);
  StepHistory& hist = state.history;
  Eigen::Matrix3Xd& a = hist.a;  // a(x_n, v_n), then a(x_{n+1}, v_{1/2})
  StepStats stats;
  const bool continues = hist.continues(kKind, state);
  if (continues) {
    stats.start_strain = hist.strain;
  } else {
    stats.start_strain = accelerations(model, state.x, state.v, state.inv_mass, a);
    ++stats.force_evals;
  }
  // The last kick's matrix is this one's (the same x_n and h/2) while this workspace holds it.
  const bool reuse = continues && hist.h == h && hist.matrix_mark != 0 && hist.matrix_mark == c.damping_mark;
  half_kick(model, state, k, a, reuse, c, stats);  // v_{1/2}
  state.x += h * state.v;                          // x_{n+1}
  hist.strain = accelerations(model, state.x, state.v, state.inv_mass, a);
  ++stats.force_evals;
  half_kick(model, state, k, a, false, c, stats);  // v_{n+1}
  a = c.dv / k;                                    // a(x_{n+1}, v_{n+1}), the kick's own equation
  c.damping_mark = hist.matrix_mark = next_mark();
  hist.h = h;
  hist.record(kKind, state);
  return stats;
}

void imex_matrix(double h, double w, double c, double m[9]) {
  const double k = 0.5 * h, d = 1.0 / (1.0 + k * c);
  for (int col = 0; col < 3; ++col) {  // the step of each unit vector of (u, u', a), a the carried a(x_n, v_n)
    double u = col == 0, v = col == 1, a = col == 2;
    v += d * k * a;                 // (1 + kc) dv = k a(u, v): the damping implicit
    u += h * v;
    a = -w * w * u - c * v;         // a(x_{n+1}, v_{1/2})
    const double dv = d * k * a;
    v += dv;
    a = dv / k;
    m[col] = u, m[3 + col] = v, m[6 + col] = a;
  }
}

double imex_limit(double w, double c) {
  if (!(w > 0.0)) return std::numeric_limits<double>::infinity();  // damping alone: every step
  // Jury's binding condition (the header): f(h) = (w h)^2 d (1 + d) - 4 (1 + d^2) < 0, true at
  // h = 2 / w (f = 4 d (1 + d) - 4 (1 + d^2) = 4 (d - 1) <= 0) and false once h grows past
  // 4 / w + 8 c / w^2 (the d (1 + d) factor falls no faster than 2 / (c h)).
  const auto stable = [&](double h) {
    const double d = 1.0 / (1.0 + 0.5 * c * h);
    return (w * h) * (w * h) * d * (1.0 + d) < 4.0 * (1.0 + d * d);
  };
  double lo = 2.0 / w, hi = lo;
  while (stable(hi)) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-14 * lo; ++i) (stable(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  return lo;
}

}  // namespace clothsim
