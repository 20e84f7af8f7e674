// The backward-Euler matrix in its spring-block pattern, checked against what it stands for:
// A p = M p - h (df/dv) p - h^2 (df/dx) p, with the derivatives taken by central finite
// differences of the force pass itself (not of the Jacobian kernel it is built from), plus
// the two properties the solver relies on: immovable bodies filtered, and positive
// definiteness under compression once the transverse term is clamped.
#include "integrators/sparse_system.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "forces.h"
#include "state.h"
#include "test_support.h"

namespace clothsim::testing {
namespace {

// A 4 x 4 sheet with every spring type, drag, corners pinned, and a dynamic sphere.
const char* kSheet = R"(
name: sheet
gravity: [0, -9.8, 0]
air_drag: 0.3
cloth:
  particles: [4, 4]
  size: [1, 1]
  center: [0, 0, 0]
  particle_mass: 0.2
  springs:
    structural: {stiffness: 900, damping: 3}
    shear:      {stiffness: 500, damping: 2}
    bend:       {stiffness: 100, damping: 1}
  pinned: corners
spheres:
  - {center: [0, -3, 0], radius: 0.5, kinematic: false, mass: 2}
)";

// Dense copy of A, column by column (3B x 3B).
Eigen::MatrixXd dense(const SpringBlockMatrix& A) {
  const int n = 3 * A.num_bodies();
  Eigen::MatrixXd out(n, n);
  Eigen::Matrix3Xd e = Eigen::Matrix3Xd::Zero(3, A.num_bodies()), y;
  for (int k = 0; k < n; ++k) {
    e.data()[k] = 1.0;
    multiply(A, e, y);
    out.col(k) = Eigen::Map<const Eigen::VectorXd>(y.data(), n);
    e.data()[k] = 0.0;
  }
  return out;
}

struct Assembled {
  Model model;
  State state;
  SpringBlockMatrix A;
  Eigen::Matrix3Xd Jv;
};

// The sheet scaled about its centre by `scale` (> 1 stretches every spring, < 1 compresses).
Assembled assemble(double scale, double h, bool clamp, bool moving,
                   const std::vector<std::string>& sets = {}) {
  Assembled s{model_from_yaml(kSheet, sets), {}, {}, {}};
  s.state = initial_state(s.model);
  const int P = s.model.num_particles;
  s.state.x.leftCols(P) *= scale;
  std::srand(7);
  s.state.x.leftCols(P) += 1e-3 * Eigen::Matrix3Xd::Random(3, P);  // out of plane too
  if (moving) s.state.v = Eigen::Matrix3Xd::Random(3, s.model.num_bodies());
  for (int b = 0; b < s.model.num_bodies(); ++b)
    if (s.state.inv_mass[b] == 0.0) s.state.v.col(b).setZero();
  build_pattern(s.model, s.A);
  assemble_backward_euler_matrix(s.model, s.state.x, s.state.v, s.state.inv_mass, h, clamp, s.A, s.Jv);
  return s;
}

TEST(SparseSystem, MatrixIsMassMinusHDfDvMinusHSquaredDfDxByFiniteDifferences) {
  // v = 0: the damper's (dropped) position term vanishes, so A is the exact Jacobian of the
  // backward-Euler residual; stretched springs: no clamp involved.
  const double h = 0.01, eps = 1e-6;
  Assembled s = assemble(1.1, h, /*clamp=*/false, /*moving=*/false);
  const Model& m = s.model;
  const Eigen::VectorXd& w = s.state.inv_mass;
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, m.num_bodies()), Ap, fp, fm;
  for (int b = 0; b < m.num_bodies(); ++b)
    if (w[b] == 0.0) p.col(b).setZero();  // the filtered subspace: dv = 0 there
  multiply(s.A, p, Ap);

  total_forces(m, s.state.x + eps * p, s.state.v, w, fp);
  total_forces(m, s.state.x - eps * p, s.state.v, w, fm);
  const Eigen::Matrix3Xd dfdx_p = (fp - fm) / (2 * eps);
  total_forces(m, s.state.x, s.state.v + eps * p, w, fp);
  total_forces(m, s.state.x, s.state.v - eps * p, w, fm);
  const Eigen::Matrix3Xd dfdv_p = (fp - fm) / (2 * eps);
  for (int b = 0; b < m.num_bodies(); ++b) {
    if (w[b] == 0.0) continue;
    const Vec3 expected = p.col(b) / w[b] - h * dfdv_p.col(b) - h * h * dfdx_p.col(b);
    EXPECT_LT((Ap.col(b) - expected).norm(), 1e-6 * (1.0 + expected.norm())) << "body " << b;
  }
}

TEST(SparseSystem, JvIsTheExactDirectionalDerivativeOfTheForceAlongV) {
  // Baraff & Witkin's right-hand side needs (df/dx) v: with dampers and moving particles
  // (the damper's position term counts), stretched and compressed, clamped matrix or not.
  const double eps = 1e-6;
  for (const double scale : {1.1, 0.9}) {
    for (const bool clamp : {false, true}) {
      const Assembled s = assemble(scale, 0.01, clamp, true);
      Eigen::Matrix3Xd fp, fm;
      total_forces(s.model, s.state.x + eps * s.state.v, s.state.v, s.state.inv_mass, fp);
      total_forces(s.model, s.state.x - eps * s.state.v, s.state.v, s.state.inv_mass, fm);
      const Eigen::Matrix3Xd expected = (fp - fm) / (2 * eps);
      ASSERT_EQ(s.Jv.cols(), expected.cols());
      EXPECT_LT((s.Jv - expected).norm(), 1e-6 * expected.norm()) << "scale " << scale << " clamp " << clamp;
    }
  }
}

TEST(SparseSystem, MatrixIsSymmetric) {
  const Assembled s = assemble(0.9, 0.05, /*clamp=*/true, /*moving=*/true);
  const Eigen::MatrixXd D = dense(s.A);
  EXPECT_LT((D - D.transpose()).norm(), 1e-12 * D.norm());
}

TEST(SparseSystem, ImmovableBodiesAreFilteredOutOfTheSystem) {
  const Assembled s = assemble(1.1, 0.01, true, true);
  const Eigen::MatrixXd D = dense(s.A);
  for (int b = 0; b < s.model.num_bodies(); ++b) {
    if (s.state.inv_mass[b] != 0.0) continue;
    // Identity on its own block, nothing coupling it to anyone: the solve leaves dv_b = 0.
    EXPECT_EQ(D.block(3 * b, 3 * b, 3, 3), Eigen::Matrix3d::Identity());
    EXPECT_DOUBLE_EQ(D.block(3 * b, 0, 3, D.cols()).norm(), std::sqrt(3.0));
    EXPECT_EQ(s.Jv.col(b).norm(), 0.0);
  }
}

TEST(SparseSystem, DynamicSphereBlockIsItsMassAlone) {
  const Assembled s = assemble(1.1, 0.01, true, true);
  const int sphere = s.model.sphere_body(0);
  const Eigen::MatrixXd D = dense(s.A);
  EXPECT_TRUE(D.block(3 * sphere, 3 * sphere, 3, 3).isApprox(2.0 * Eigen::Matrix3d::Identity()));
  EXPECT_NEAR(D.block(3 * sphere, 0, 3, D.cols()).norm(), 2.0 * std::sqrt(3.0), 1e-12);
}

TEST(SparseSystem, ClampingCompressionKeepsTheMatrixPositiveDefiniteAtHugeSteps) {
  // Every spring at 60% of its rest length and h = 1 s: the exact transverse stiffness
  // -ks (1 - l0/l)(I - P) has the wrong sign and makes A indefinite; clamped, it is SPD.
  const Assembled exact = assemble(0.6, 1.0, /*clamp=*/false, true);
  const Assembled clamped = assemble(0.6, 1.0, /*clamp=*/true, true);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e_exact(dense(exact.A));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e_clamped(dense(clamped.A));
  EXPECT_LT(e_exact.eigenvalues().minCoeff(), 0.0);
  EXPECT_GT(e_clamped.eigenvalues().minCoeff(), 0.0);
}

TEST(SparseSystem, StretchedSpringsNeedNoClamp) {
  const Assembled exact = assemble(1.2, 1.0, false, true);
  const Assembled clamped = assemble(1.2, 1.0, true, true);
  EXPECT_EQ(dense(exact.A), dense(clamped.A));
}

}  // namespace
}  // namespace clothsim::testing
