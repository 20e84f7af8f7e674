// Block-Jacobi PCG on backward-Euler systems of a small sheet: it solves to its tolerance
// (checked with an independent product), says when it stops at its cap, and is exact in
// one iteration when the system is block diagonal (no springs: the preconditioner is A^-1).
#include "core/linear/conjugate_gradient.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"
#include "core/implicit/sparse_system.h"
#include "core/implicit/step_potential.h"
#include "core/model/state.h"

namespace clothsim::testing {
namespace {

std::string sheet(const std::string& springs) {
  return "name: sheet\ncloth:\n  particles: [6, 5]\n  size: [1, 1]\n  particle_mass: 0.1\n"
         "  pinned: top_edge\n  springs:\n" + springs;
}
const std::string kAllSprings =
    "    structural: {stiffness: 5000, damping: 5}\n"
    "    shear: {stiffness: 3000, damping: 3}\n"
    "    bend: {stiffness: 500, damping: 1}\n";

struct System {
  Model model;
  SpringBlockMatrix A;
  Eigen::Matrix3Xd b;
};

System system(const std::string& springs, double h) {
  System s{model_from_yaml(sheet(springs)), {}, {}};
  State st = initial_state(s.model);
  std::srand(3);
  st.x += 0.02 * Eigen::Matrix3Xd::Random(3, s.model.num_bodies());
  st.v = Eigen::Matrix3Xd::Random(3, s.model.num_bodies());
  std::vector<double> start_length;
  step_lengths(s.model, st.x, start_length);
  build_pattern(s.model, s.A);
  assemble_step_hessian(s.model, st.inv_mass, h, start_length, st.x + h * st.v, HessianBlocks::Projected, s.A);
  s.b = Eigen::Matrix3Xd::Random(3, s.model.num_bodies());
  for (int i = 0; i < s.model.num_bodies(); ++i)
    if (st.inv_mass[i] == 0.0) s.b.col(i).setZero();
  return s;
}

TEST(ConjugateGradient, SolvesABackwardEulerSystemToItsTolerance) {
  const System s = system(kAllSprings, 0.02);  // h^2 k / m = 20: far from mass-dominated
  Eigen::Matrix3Xd x, Ax;
  CgBuffers buffers;
  const CgResult r = solve_pcg(s.A, s.b, x, CgSettings{500, 1e-10}, buffers);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.iterations, 1);
  EXPECT_LE(r.relative_residual, 1e-10);
  multiply(s.A, x, Ax);
  EXPECT_LE((s.b - Ax).norm(), 1e-9 * s.b.norm());  // the recurrence did not drift
}

TEST(ConjugateGradient, SaysSoWhenItStopsAtItsIterationCap) {
  const System s = system(kAllSprings, 0.02);
  Eigen::Matrix3Xd x;
  CgBuffers buffers;
  const CgResult r = solve_pcg(s.A, s.b, x, CgSettings{2, 1e-14}, buffers);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_GT(r.relative_residual, 1e-14);
}

TEST(ConjugateGradient, ZeroRightHandSideNeedsNoIteration) {
  const System s = system(kAllSprings, 0.02);
  Eigen::Matrix3Xd x = Eigen::Matrix3Xd::Ones(3, s.model.num_bodies());
  CgBuffers buffers;
  const CgResult r = solve_pcg(s.A, Eigen::Matrix3Xd::Zero(3, s.model.num_bodies()), x, CgSettings{10, 1e-8}, buffers);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(x.norm(), 0.0);
}

TEST(ConjugateGradient, BlockJacobiIsExactWithoutSprings) {
  const System s = system("    {}\n", 0.02);
  ASSERT_EQ(s.model.springs.size(), 0u);
  Eigen::Matrix3Xd x;
  CgBuffers buffers;
  const CgResult r = solve_pcg(s.A, s.b, x, CgSettings{10, 1e-12}, buffers);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 1);
}

TEST(ConjugateGradient, AWarmStartNearTheSolutionNeedsFewerIterations) {
  const System s = system(kAllSprings, 0.02);
  Eigen::Matrix3Xd exact, x;
  CgBuffers buffers;
  const CgResult cold = solve_pcg(s.A, s.b, exact, CgSettings{500, 1e-12}, buffers);
  ASSERT_TRUE(cold.converged);
  // From the solution itself: nothing to do.
  x = exact;
  EXPECT_EQ(solve_pcg(s.A, s.b, x, CgSettings{500, 1e-10, 0.0, true}, buffers).iterations, 0);
  // From a guess 1e-3 off: converges, in fewer iterations than from zero, to the same answer.
  std::srand(11);
  x = exact + 1e-3 * exact.norm() / std::sqrt(double(exact.size())) * Eigen::Matrix3Xd::Random(3, exact.cols());
  const CgResult warm = solve_pcg(s.A, s.b, x, CgSettings{500, 1e-12, 0.0, true}, buffers);
  EXPECT_TRUE(warm.converged);
  EXPECT_LT(warm.iterations, cold.iterations);
  EXPECT_LT((x - exact).norm(), 1e-8 * exact.norm());
}

TEST(ConjugateGradient, StopsAtTheAbsoluteAccuracyTheCallerNeeds) {
  const System s = system(kAllSprings, 0.02);
  Eigen::Matrix3Xd x, Ax;
  CgBuffers buffers;
  const double need = 1e-3 * s.b.norm();
  const CgResult loose = solve_pcg(s.A, s.b, x, CgSettings{500, 1e-14, need}, buffers);
  EXPECT_TRUE(loose.converged);
  multiply(s.A, x, Ax);
  EXPECT_LE((s.b - Ax).norm(), need * (1 + 1e-9));
  const CgResult tight = solve_pcg(s.A, s.b, x, CgSettings{500, 1e-14}, buffers);
  EXPECT_LT(loose.iterations, tight.iterations);
}

TEST(ConjugateGradient, AFilteredSolveNeverMovesAlongHeldNormalsAndSolvesTheRest) {
  const System s = system(kAllSprings, 0.02);
  VelocityFilter filter;
  filter.body = {20, 25, 27};
  filter.normal = {Vec3::UnitY(), Vec3(1, 1, 0).normalized(), Vec3::UnitZ()};
  Eigen::Matrix3Xd b = s.b, x, Ax;
  filter.apply(b);
  CgBuffers buffers;
  const CgResult r = solve_pcg(s.A, b, x, CgSettings{500, 1e-12}, buffers, &filter);
  ASSERT_TRUE(r.converged);
  for (std::size_t c = 0; c < filter.size(); ++c)
    EXPECT_LT(std::abs(filter.normal[c].dot(x.col(filter.body[c]))), 1e-14 * x.norm());
  multiply(s.A, x, Ax);
  Eigen::Matrix3Xd residual = b - Ax;
  filter.apply(residual);  // S (b - A x) = 0: the reduced system S A S x = S b is solved
  EXPECT_LE(residual.norm(), 1e-10 * b.norm());
}

TEST(ConjugateGradient, EveryTruncatedIterateFromZeroDescends) {
  // Stopped at any iteration, x_k has b . x_k > 0: a descent direction for the Newton step.
  const System s = system(kAllSprings, 0.02);
  for (int cap = 1; cap <= 6; ++cap) {
    Eigen::Matrix3Xd x;
    CgBuffers buffers;
    solve_pcg(s.A, s.b, x, CgSettings{cap, 1e-14}, buffers);
    EXPECT_GT(s.b.cwiseProduct(x).sum(), 0.0) << "after " << cap << " iterations";
  }
}

TEST(ConjugateGradient, StopsAtNegativeCurvatureWithTheFirstDirectionAndSaysSo) {
  System s = system(kAllSprings, 0.02);
  for (auto& block : s.A.diag) block = -block;  // negative definite: the first p has p.Ap < 0
  s.A.refresh_copies();  // (the SIMD mat-vec reads these copies)
  Eigen::Matrix3Xd x;
  CgBuffers buffers;
  const CgResult r = solve_pcg(s.A, s.b, x, CgSettings{50, 1e-10}, buffers);
  EXPECT_FALSE(r.converged);
  EXPECT_TRUE(r.negative_curvature);
  EXPECT_EQ(r.iterations, 0);
  // The first direction itself, the preconditioned right-hand side: still downhill (b . x > 0),
  // so a Newton solve always has a step to search along.
  for (int i = 0; i < s.A.num_bodies(); ++i)
    EXPECT_TRUE(x.col(i).isApprox(s.A.diag_inverse[i] * s.b.col(i), 1e-12) || s.b.col(i).isZero())
        << "body " << i;
  EXPECT_GT(s.b.cwiseProduct(x).sum(), 0.0);
}

// The quadratic model CG minimises, q(x) = 1/2 x.A x - b.x (q(0) = 0).
double model_value(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, const Eigen::Matrix3Xd& x) {
  Eigen::Matrix3Xd Ax;
  multiply(A, x, Ax);
  return 0.5 * x.cwiseProduct(Ax).sum() - b.cwiseProduct(x).sum();
}

// x^T M x for block Jacobi's M, the blocks of A's diagonal.
double block_jacobi_norm2(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& x) {
  double sum = 0.0;
  for (int i = 0; i < A.num_bodies(); ++i) sum += x.col(i).dot(A.diag[i] * x.col(i));
  return sum;
}

TEST(ConjugateGradient, SteihaugStopsOnTheRadiusInThePreconditionersNormAndLowersTheModel) {
  const System s = system(kAllSprings, 0.02);
  Eigen::Matrix3Xd x_full, x;
  CgBuffers buffers;
  CgSettings settings{500, 1e-12};
  settings.trust_region = true;  // unbounded: the solve, with its length measured
  const CgResult full = solve_pcg(s.A, s.b, x_full, settings, buffers);
  ASSERT_TRUE(full.converged);
  EXPECT_FALSE(full.boundary);
  EXPECT_NEAR(full.step_norm, std::sqrt(block_jacobi_norm2(s.A, x_full)), 1e-8 * full.step_norm);
  for (const double fraction : {0.05, 0.3, 0.9}) {
    settings.trust_radius = fraction * full.step_norm;
    const CgResult r = solve_pcg(s.A, s.b, x, settings, buffers);
    EXPECT_TRUE(r.boundary) << fraction;
    EXPECT_FALSE(r.converged);
    EXPECT_NEAR(std::sqrt(block_jacobi_norm2(s.A, x)), settings.trust_radius, 1e-8 * full.step_norm) << fraction;
    EXPECT_NEAR(r.step_norm, settings.trust_radius, 1e-12 * full.step_norm);
    // Within the region the model falls, less than at the unbounded minimiser.
    const double q = model_value(s.A, s.b, x);
    EXPECT_LT(q, 0.0) << fraction;
    EXPECT_GT(q, model_value(s.A, s.b, x_full)) << fraction;
  }
}

TEST(ConjugateGradient, SteihaugGoesToTheRadiusAlongNegativeCurvature) {
  System s = system(kAllSprings, 0.02);
  for (auto& block : s.A.diag) block = -block;  // the first p has p.Ap < 0
  const std::vector<Mat3>& preconditioned = s.A.diag_projected;  // block Jacobi's M, still SPD
  s.A.refresh_copies();
  const auto norm = [&preconditioned](const Eigen::Matrix3Xd& v) {  // |v|_M
    double sum = 0.0;
    for (Eigen::Index i = 0; i < v.cols(); ++i) sum += v.col(i).dot(preconditioned[i] * v.col(i));
    return std::sqrt(sum);
  };
  Eigen::Matrix3Xd first, x;  // truncated CG's answer: the first direction, unscaled
  CgBuffers buffers;
  solve_pcg(s.A, s.b, first, CgSettings{50, 1e-10}, buffers);
  CgSettings settings{50, 1e-10};
  settings.trust_region = true;
  settings.trust_radius = 3.0 * norm(first);
  const CgResult r = solve_pcg(s.A, s.b, x, settings, buffers);
  EXPECT_TRUE(r.negative_curvature);
  EXPECT_TRUE(r.boundary);
  // On the boundary, not the truncated iterate: |x|_M = radius, and the model lower than the
  // unscaled first direction's (where truncated CG stopped before).
  EXPECT_NEAR(norm(x), settings.trust_radius, 1e-12 * settings.trust_radius);
  EXPECT_NEAR(r.step_norm, settings.trust_radius, 1e-12 * settings.trust_radius);
  EXPECT_GT(s.b.cwiseProduct(x).sum(), 0.0);  // downhill
  EXPECT_LT(model_value(s.A, s.b, x), model_value(s.A, s.b, first));
}

TEST(ConjugateGradient, ReturnsTheModelsValueAtItsAnswerWhereverItStops) {
  // q(x) = 1/2 x.A x - b.x by an independent product, against CG's recurrence: converged, cut
  // at its cap, on the radius, along negative curvature, from a guess, and filtered.
  System s = system(kAllSprings, 0.02);
  const auto check = [](const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, const Eigen::Matrix3Xd& x,
                        const CgResult& r, const char* what) {
    const double q = model_value(A, b, x);
    EXPECT_LT(q, 0.0) << what;  // every answer lowers the model
    EXPECT_NEAR(r.model_value, q, 1e-10 * std::abs(q)) << what;
  };
  Eigen::Matrix3Xd x, x_full;
  CgBuffers buffers;
  CgSettings settings{500, 1e-12};
  settings.trust_region = true;
  const CgResult full = solve_pcg(s.A, s.b, x_full, settings, buffers);
  check(s.A, s.b, x_full, full, "converged");
  x = x_full;
  check(s.A, s.b, x, solve_pcg(s.A, s.b, x, CgSettings{3, 1e-12}, buffers), "cut at 3 iterations");
  settings.trust_radius = 0.3 * full.step_norm;
  check(s.A, s.b, x, solve_pcg(s.A, s.b, x, settings, buffers), "on the radius");
  std::srand(5);
  x = x_full + 0.1 * x_full.norm() / std::sqrt(double(x.size())) * Eigen::Matrix3Xd::Random(3, x.cols());
  check(s.A, s.b, x, solve_pcg(s.A, s.b, x, CgSettings{2, 1e-12, 0.0, true}, buffers), "from a guess");
  VelocityFilter filter;
  filter.body = {20, 25, 27};
  filter.normal = {Vec3::UnitY(), Vec3(1, 1, 0).normalized(), Vec3::UnitZ()};
  Eigen::Matrix3Xd b = s.b;
  filter.apply(b);
  check(s.A, b, x, solve_pcg(s.A, b, x, CgSettings{4, 1e-12}, buffers, &filter), "filtered");
  for (auto& block : s.A.diag) block = -block;  // negative definite along the first p
  s.A.refresh_copies();
  // (q is unbounded below here: the truncated first direction, then the boundary along it)
  const CgResult first = solve_pcg(s.A, s.b, x, CgSettings{50, 1e-10}, buffers);
  ASSERT_TRUE(first.negative_curvature);
  check(s.A, s.b, x, first, "the first direction at negative curvature");
  settings.trust_radius = 2.0 * full.step_norm;
  const CgResult bounded = solve_pcg(s.A, s.b, x, settings, buffers);
  ASSERT_TRUE(bounded.boundary && bounded.negative_curvature);
  check(s.A, s.b, x, bounded, "the boundary along negative curvature");
}

}  // namespace
}  // namespace clothsim::testing
