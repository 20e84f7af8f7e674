// The spring-damper kernel on hand-computed cases, and its Jacobians against central
// finite differences of the force itself.
#include "core/springs/spring_force.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

#include "core/model/forces.h"

namespace clothsim {
namespace {

TEST(SpringForce, StretchedSpringPullsTheEndsTogether) {
  // |d| = 2, l0 = 1, ks = 10: f_a = -10 (2 - 1) (1, 0, 0).
  const Vec3 f = spring_damper_force({2, 0, 0}, {0, 0, 0}, Vec3::Zero(), Vec3::Zero(), 1.0, 10.0, 0.0);
  EXPECT_NEAR(f.x(), -10.0, 1e-12);
  EXPECT_NEAR(f.y(), 0.0, 1e-12);
  EXPECT_NEAR(f.z(), 0.0, 1e-12);
}

TEST(SpringForce, CompressedSpringPushesTheEndsApart) {
  // d = (0, 0.5, 0), l0 = 2, ks = 4: f_a = -4 (0.5 - 2) (0, 1, 0) = (0, 6, 0).
  const Vec3 f = spring_damper_force({0, 1.5, 0}, {0, 1, 0}, Vec3::Zero(), Vec3::Zero(), 2.0, 4.0, 0.0);
  EXPECT_NEAR(f.y(), 6.0, 1e-12);
}

TEST(SpringForce, DamperOpposesTheRateOfStretchOnly) {
  // d = (3, 4, 0), u = (0.6, 0.8, 0), at rest length. va - vb = (1, 0, 0): (vr.u) = 0.6,
  // f_a = -kd 0.6 u = -2 * 0.6 * (0.6, 0.8, 0) = (-0.72, -0.96, 0).
  const Vec3 f = spring_damper_force({3, 4, 0}, {0, 0, 0}, {1, 0, 0}, {0, 0, 0}, 5.0, 100.0, 2.0);
  EXPECT_NEAR(f.x(), -0.72, 1e-12);
  EXPECT_NEAR(f.y(), -0.96, 1e-12);
  // A velocity across the spring (a rotation) is not damped at all.
  const Vec3 g = spring_damper_force({3, 4, 0}, {0, 0, 0}, {-0.8, 0.6, 0}, {0, 0, 0}, 5.0, 100.0, 2.0);
  EXPECT_NEAR(g.norm(), 0.0, 1e-12);
}

TEST(SpringForce, CoincidentEndsGiveZeroForceNotNaN) {
  const Vec3 f = spring_damper_force({1, 1, 1}, {1, 1, 1}, {1, 0, 0}, Vec3::Zero(), 1.0, 10.0, 1.0);
  EXPECT_TRUE(f.allFinite());
  EXPECT_EQ(f.norm(), 0.0);
}

TEST(SpringForce, SystemPassAppliesEqualAndOppositeForces) {
  Springs s;
  s.a = {0};
  s.b = {1};
  s.rest = {1.0};
  s.ks = {10.0};
  s.kd = {3.0};
  s.type = {SpringType::Structural};
  Eigen::Matrix3Xd x(3, 2), v(3, 2), f = Eigen::Matrix3Xd::Zero(3, 2);
  x << 2, 0, 0.5, 0, -1, 0;
  v << 1, 0, 0, 0.5, 2, 0;
  // It also returns the largest strain, read off the lengths it computes anyway.
  EXPECT_NEAR(accumulate_spring_forces_scalar(s, x, v, f), std::sqrt(4 + 1 + 0.25) - 1.0, 1e-12);
  const Vec3 expected = spring_damper_force(x.col(0), x.col(1), v.col(0), v.col(1), 1.0, 10.0, 3.0);
  EXPECT_NEAR((f.col(0) - expected).norm(), 0.0, 1e-12);
  EXPECT_NEAR((f.col(0) + f.col(1)).norm(), 0.0, 1e-12);
}

// Central differences of `f` (a Vec3 -> Vec3 function) at `at`, column by column.
template <class F>
Mat3 numeric_jacobian(const F& f, const Vec3& at) {
  Mat3 J;
  const double eps = 1e-6;
  for (int c = 0; c < 3; ++c) {
    Vec3 p = at, m = at;
    p[c] += eps;
    m[c] -= eps;
    J.col(c) = (f(p) - f(m)) / (2 * eps);
  }
  return J;
}

TEST(SpringJacobian, MatchesFiniteDifferencesStretchedCompressedAndMoving) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 xa(U(rng), U(rng), U(rng)), xb(U(rng), U(rng), U(rng));
    const Vec3 va(U(rng), U(rng), U(rng)), vb(U(rng), U(rng), U(rng));
    const double l = (xa - xb).norm();
    const double l0 = l * (trial % 2 ? 0.7 : 1.4);  // stretched and compressed
    const double ks = 1000.0, kd = 5.0;
    const SpringJacobian J = spring_damper_jacobian(xa, xb, va, vb, l0, ks, kd);
    const Mat3 nx = numeric_jacobian([&](const Vec3& x) { return spring_damper_force(x, xb, va, vb, l0, ks, kd); }, xa);
    const Mat3 nv = numeric_jacobian([&](const Vec3& v) { return spring_damper_force(xa, xb, v, vb, l0, ks, kd); }, va);
    EXPECT_LT((J.dfdx() - nx).norm(), 1e-5 * (1.0 + nx.norm())) << "trial " << trial;
    EXPECT_LT((J.dfdv - nv).norm(), 1e-6 * (1.0 + nv.norm())) << "trial " << trial;
  }
}

TEST(SpringJacobian, StiffnessPartIsSymmetricAndDamperPartVanishesAtRest) {
  const Vec3 xa(0.3, 1.2, -0.4), xb(-0.2, 0.1, 0.5);
  const SpringJacobian J = spring_damper_jacobian(xa, xb, Vec3::Zero(), Vec3::Zero(), 0.8, 500.0, 7.0);
  EXPECT_LT((J.dfdx_stiffness - J.dfdx_stiffness.transpose()).norm(), 1e-12);
  EXPECT_LT(J.dfdx_damping.norm(), 1e-12);  // no relative velocity: no damper position term
  EXPECT_LT((J.dfdv - J.dfdv.transpose()).norm(), 1e-12);
}

TEST(SpringJacobian, OtherEndBlocksAreTheNegatives) {
  // f_a depends on x_a - x_b only, so df_a/dx_b = -df_a/dx_a: check by differencing in x_b.
  const Vec3 xa(0.5, 0.2, 0.1), xb(-0.4, 0.3, 0.2), va(0.3, -0.2, 0.1), vb(-0.1, 0.4, 0.0);
  const SpringJacobian J = spring_damper_jacobian(xa, xb, va, vb, 0.6, 300.0, 4.0);
  const Mat3 n = numeric_jacobian([&](const Vec3& x) { return spring_damper_force(xa, x, va, vb, 0.6, 300.0, 4.0); }, xb);
  EXPECT_LT((n + J.dfdx()).norm(), 1e-5 * (1.0 + n.norm()));
}

}  // namespace
TEST(StepSpring, TensionIsTheEnergysDerivativeInLength) {
  const double rest = 1.0, ln = 1.05, ks = 300.0, kd = 4.0, h = 0.02, eps = 1e-6;
  for (const double l : {0.7, 1.0, 1.02, 1.3}) {
    const double numeric = (step_spring_energy(l + eps, rest, ln, ks, kd, h) -
                            step_spring_energy(l - eps, rest, ln, ks, kd, h)) / (2 * eps);
    EXPECT_NEAR(step_spring_tension(l, rest, ln, ks, kd, h), numeric, 1e-6 * (1 + std::abs(numeric)));
  }
}

TEST(StepSpring, DamperRateIsTheLengthsChangeOverTheStepAndMatchesTheSeedsDamperAlongTheAxis) {
  // Moving straight along the spring (no rotation), (l - ln) / h is exactly u . (v_a - v_b) for
  // a step at constant velocity: the step damper and the seed's damper agree.
  const double h = 0.01, ks = 0.0, kd = 7.0;
  const Vec3 xa(1.0, 0, 0), xb(0, 0, 0), va(0.3, 0, 0), vb(0, 0, 0);
  const double l = (xa + h * va - xb - h * vb).norm(), ln = (xa - xb).norm();
  const Vec3 seed = spring_damper_force(xa + h * va, xb + h * vb, va, vb, 1.0, ks, kd);
  EXPECT_NEAR(-step_spring_tension(l, 1.0, ln, ks, kd, h), seed.x(), 1e-12);
}

TEST(StepSpring, HessianMatchesFiniteDifferencesOfTheForceAndItsProjectionIsPositiveSemiDefinite) {
  const double rest = 1.0, ln = 1.0, ks = 500.0, kd = 3.0, h = 0.05;
  for (const double scale : {1.3, 0.7}) {
    const Vec3 d = scale * Vec3(0.6, 0.8, 0.1).normalized();
    // f_a = -T u; K = -df_a/dx_a, by central differences of -T u in d.
    const auto force = [&](const Vec3& dd) {
      return Vec3(-step_spring_tension(dd.norm(), rest, ln, ks, kd, h) * dd / dd.norm());
    };
    const Mat3 numeric = -numeric_jacobian(force, d);
    const Mat3 exact = step_spring_hessian(d, rest, ln, ks, kd, h, false);
    EXPECT_LT((exact - numeric).norm(), 1e-5 * numeric.norm()) << "scale " << scale;
    const Mat3 projected = step_spring_hessian(d, rest, ln, ks, kd, h, true);
    const Eigen::SelfAdjointEigenSolver<Mat3> e(projected);
    EXPECT_GE(e.eigenvalues().minCoeff(), 0.0);
    if (scale > 1.0) EXPECT_TRUE(projected.isApprox(exact)) << "stretched: nothing to project";
    else EXPECT_LT(Eigen::SelfAdjointEigenSolver<Mat3>(exact).eigenvalues().minCoeff(), 0.0);
  }
}

}  // namespace clothsim
