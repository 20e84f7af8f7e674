// The barrier's kernels: its derivatives and the pair gradients and Hessians against central
// finite differences, its smoothness where it activates, the stiffness rule, the closed-form
// step bounds, and the friction mollifier and potential.
#include "core/model/barrier_kernels.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

namespace clothsim {
namespace {

const BarrierParams kParams{0.01, barrier_kappa_for_stiffness(900.0, 0.01)};

TEST(BarrierKernels, DerivativesMatchFiniteDifferencesInsideTheReach) {
  for (double d : {1e-4, 1e-3, 0.005, 0.009, 0.0099}) {
    const double e = 1e-7 * d;
    const double fd1 = (barrier_energy(d + e, kParams) - barrier_energy(d - e, kParams)) / (2 * e);
    const double fd2 = (barrier_derivative(d + e, kParams) - barrier_derivative(d - e, kParams)) / (2 * e);
    EXPECT_NEAR(barrier_derivative(d, kParams), fd1, 1e-6 * std::abs(fd1) + 1e-12) << d;
    EXPECT_NEAR(barrier_second_derivative(d, kParams), fd2, 1e-6 * std::abs(fd2) + 1e-9) << d;
  }
}

TEST(BarrierKernels, IsRepulsiveConvexAndInfiniteAtContact) {
  for (double d : {1e-6, 1e-3, 0.005, 0.0099}) {
    EXPECT_GT(barrier_energy(d, kParams), 0.0);
    EXPECT_LT(barrier_derivative(d, kParams), 0.0);
    EXPECT_GT(barrier_second_derivative(d, kParams), 0.0);
  }
  EXPECT_EQ(barrier_energy(0.0, kParams), INFINITY);
  EXPECT_EQ(barrier_energy(-1e-3, kParams), INFINITY);
  EXPECT_EQ(barrier_energy(0.01, kParams), 0.0);
  EXPECT_EQ(barrier_derivative(0.02, kParams), 0.0);
}

// The force is C5 where a contact activates: b' vanishes as s^6 and b'' as s^5 (s = dhat - d),
// so the force and its first five derivatives are continuous there and RK4's order survives.
TEST(BarrierKernels, ForceVanishesToFifthOrderWhereAContactActivates) {
  const double dhat = kParams.dhat;
  for (double s : {1e-5, 5e-6}) {
    const double ratio1 = barrier_derivative(dhat - s, kParams) / barrier_derivative(dhat - 2 * s, kParams);
    const double ratio2 = barrier_second_derivative(dhat - s, kParams) / barrier_second_derivative(dhat - 2 * s, kParams);
    EXPECT_NEAR(ratio1, 1.0 / 64.0, 1e-3) << s;  // b' ~ s^6
    EXPECT_NEAR(ratio2, 1.0 / 32.0, 1e-3) << s;  // b'' ~ s^5
  }
}

TEST(BarrierKernels, StiffnessIsTheCurvatureAtHalfTheReach) {
  EXPECT_NEAR(barrier_second_derivative(0.005, kParams), 900.0, 1e-9);
  // The default rule: a weight w is held at dhat / 2.
  const double k = barrier_stiffness_for_weight(9.8, 0.01);
  const BarrierParams p{0.01, barrier_kappa_for_stiffness(k, 0.01)};
  EXPECT_NEAR(-barrier_derivative(0.005, p), 9.8, 1e-9);
}

// Central differences of the energy and of the gradient at a point x.
template <class Energy, class Gradient>
void expect_fd(const Energy& energy, const Gradient& gradient, const BarrierVec3& x, const BarrierVec3& g,
               const BarrierMat3& H) {
  const double e = 1e-8;
  for (int k = 0; k < 3; ++k) {
    BarrierVec3 dx = BarrierVec3::Zero();
    dx[k] = e;
    EXPECT_NEAR(g[k], (energy(x + dx) - energy(x - dx)) / (2 * e), 1e-5 * g.norm() + 1e-9) << k;
    const BarrierVec3 column = (gradient(x + dx) - gradient(x - dx)) / (2 * e);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(H(r, k), column[r], 1e-5 * H.norm() + 1e-6) << r << "," << k;
  }
}

TEST(BarrierKernels, PlaneGradientAndHessianMatchFiniteDifferences) {
  const BarrierVec3 x(0.3, -1.996, 0.2);
  const PointBarrier b = plane_barrier(x, -2.0, kParams);
  ASSERT_TRUE(b.active());
  expect_fd([](const BarrierVec3& y) { return plane_barrier(y, -2.0, kParams).energy; },
            [](const BarrierVec3& y) { return plane_barrier(y, -2.0, kParams).gradient; }, x, b.gradient, b.hessian);
}

TEST(BarrierKernels, SphereGradientAndExactHessianMatchFiniteDifferences) {
  const BarrierVec3 c(0.1, 0.0, -0.2), x = c + (1.0 + 0.004) * BarrierVec3(0.48, 0.8, 0.36).normalized();
  const PointBarrier b = sphere_barrier(x, c, 1.0, kParams, false);
  ASSERT_TRUE(b.active());
  expect_fd([&](const BarrierVec3& y) { return sphere_barrier(y, c, 1.0, kParams, false).energy; },
            [&](const BarrierVec3& y) { return sphere_barrier(y, c, 1.0, kParams, false).gradient; }, x, b.gradient,
            b.hessian);
  // Projected: positive semi-definite, the normal curvature kept.
  const PointBarrier projected = sphere_barrier(x, c, 1.0, kParams, true);
  Eigen::SelfAdjointEigenSolver<BarrierMat3> eig(projected.hessian);
  EXPECT_GE(eig.eigenvalues().minCoeff(), 0.0);
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<BarrierMat3>(b.hessian).eigenvalues().minCoeff(), 0.0);
  EXPECT_NEAR(b.normal.dot(projected.hessian * b.normal), b.normal.dot(b.hessian * b.normal), 1e-9);
}

TEST(BarrierKernels, PlaneStepBoundKeepsTheAskedFractionOfTheGap) {
  EXPECT_DOUBLE_EQ(plane_step_bound(0.004, -0.1, 0.1), 0.9 * 0.004 / 0.1);
  EXPECT_EQ(plane_step_bound(0.004, +0.1, 0.1), 1.0);   // leaving
  EXPECT_EQ(plane_step_bound(0.004, -0.001, 0.1), 1.0); // never gets there within the step
}

TEST(BarrierKernels, SphereStepBoundStopsTheLineAtTheKeptDistance) {
  const BarrierVec3 p(0.0, 1.005, 0.0), q(0.3, -0.5, 0.1);
  const double alpha = sphere_step_bound(p, q, 1.0, 0.1);
  ASSERT_LT(alpha, 1.0);
  EXPECT_NEAR((p + alpha * q).norm() - 1.0, 0.1 * 0.005, 1e-12);
  for (double a = 0.0; a < alpha; a += alpha / 64) EXPECT_GT((p + a * q).norm() - 1.0, 0.1 * 0.005 - 1e-15);
  EXPECT_EQ(sphere_step_bound(p, -q, 1.0, 0.1), 1.0);  // moving away
  EXPECT_EQ(sphere_step_bound(p, BarrierVec3(1e-3, 0, 0), 1.0, 0.1), 1.0);  // a tangent graze that stays out
}

TEST(FrictionKernels, MollifierIsC1AndReachesCoulomb) {
  const double eps = 1e-3;
  EXPECT_DOUBLE_EQ(friction_f1(0.0, eps), 0.0);
  EXPECT_DOUBLE_EQ(friction_f1(eps, eps), 1.0);
  EXPECT_DOUBLE_EQ(friction_f1(2 * eps, eps), 1.0);
  const double e = 1e-9;
  EXPECT_NEAR((friction_f1(eps, eps) - friction_f1(eps - e, eps)) / e, 0.0, 1e-2);  // slope 0 at eps (2 / eps = 2000 at 0)
  EXPECT_NEAR((friction_f0(0.5 * eps + e, eps) - friction_f0(0.5 * eps - e, eps)) / (2 * e), friction_f1(0.5 * eps, eps), 1e-6);
  const BarrierVec3 f = friction_force(BarrierVec3(0.1, 0, 0), 20.0, 0.5, eps);
  EXPECT_NEAR(f.x(), -10.0, 1e-12);  // sliding: mu lambda against the motion
}

TEST(BarrierKernels, TheSmoothDrapesBarrierTakesAPushedParticlesEnergyBeforeAMillimetre) {
  // scenes/drape_smooth.yaml: 1e6 N/m within 0.01 m; the ball pushes at up to 7 m/s, a 1 kg
  // particle's 24.5 J. Its comment quotes b(0.001 m) = 57.9 J.
  const BarrierParams p{0.01, barrier_kappa_for_stiffness(1.0e6, 0.01)};
  EXPECT_NEAR(barrier_energy(0.001, p), 57.9, 0.05);
  EXPECT_GT(barrier_energy(0.001, p), 0.5 * 1.0 * 7.0 * 7.0);
}

TEST(FrictionKernels, LaggedPotentialGradientAndHessianMatchFiniteDifferences) {
  const BarrierVec3 n = BarrierVec3(0.2, 1.0, 0.1).normalized();
  const BarrierMat3 P = BarrierMat3::Identity() - n * n.transpose();
  const double eps = 2e-3;
  for (const BarrierVec3& raw : {BarrierVec3(5e-4, 0.0, 3e-4), BarrierVec3(0.01, 0.002, -0.004)}) {
    const BarrierVec3 x = P * raw;  // the tangential displacement is u = P x
    const auto energy = [&](const BarrierVec3& y) { return friction_potential(P * y, n, 7.0, 0.4, eps).energy; };
    const auto gradient = [&](const BarrierVec3& y) { return friction_potential(P * y, n, 7.0, 0.4, eps).gradient; };
    const FrictionTerm t = friction_potential(x, n, 7.0, 0.4, eps);
    expect_fd(energy, gradient, x, t.gradient, t.hessian);
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<BarrierMat3>(t.hessian).eigenvalues().minCoeff(), -1e-9);
  }
}

}  // namespace
}  // namespace clothsim
