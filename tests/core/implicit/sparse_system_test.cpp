// The Newton matrix of implicit Euler in its spring-block pattern, checked against what it
// stands for: the Hessian of the step potential Phi (step_potential.h), by central finite
// differences of Phi's gradient (not of the kernel the matrix is built from), plus the
// properties the solver relies on: symmetry, immovable bodies filtered, positive definiteness
// of the projected matrix under compression, and a preconditioner that is always SPD.
#include "core/implicit/sparse_system.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <string>

#include "test_support.h"
#include "core/implicit/step_potential.h"
#include "core/model/state.h"

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
  std::vector<double> start_length;
  Eigen::Matrix3Xd dv, y;
  SpringBlockMatrix A;
};

// The sheet scaled about its centre by `scale` (> 1 stretches every spring, < 1 compresses),
// moving, with a random iterate dv; A assembled at its end-of-step positions.
Assembled assemble(double scale, double h, bool project, bool moving = true,
                   const std::vector<std::string>& sets = {}) {
  Assembled s{model_from_yaml(kSheet, sets), {}, {}, {}, {}, {}};
  s.state = initial_state(s.model);
  const int B = s.model.num_bodies(), P = s.model.num_particles;
  std::srand(7);
  s.state.x.leftCols(P) += 1e-3 * Eigen::Matrix3Xd::Random(3, P);  // out of plane too
  s.state.v = (moving ? 0.1 : 0.0) * Eigen::Matrix3Xd::Random(3, B);
  s.dv = (moving ? 0.1 : 0.0) * Eigen::Matrix3Xd::Random(3, B);
  for (int b = 0; b < B; ++b)
    if (s.state.inv_mass[b] == 0.0) s.state.v.col(b).setZero(), s.dv.col(b).setZero();
  step_lengths(s.model, s.state.x, s.start_length);
  // Scale the end of the step about the centre: y = scale x_n + h (v + dv) moves through
  // dv_scale = (scale - 1) x_n / h, so springs end stretched or compressed by the factor.
  s.dv.leftCols(P) += (scale - 1.0) / h * s.state.x.leftCols(P);
  for (int b = 0; b < P; ++b)
    if (s.state.inv_mass[b] == 0.0) s.dv.col(b).setZero();
  Eigen::Matrix3Xd r;
  step_potential(s.model, s.state, h, s.start_length, s.dv, s.y, r);
  build_pattern(s.model, s.A);
  assemble_step_hessian(s.model, s.state.inv_mass, h, s.start_length, s.y, project ? HessianBlocks::Projected : HessianBlocks::Exact, s.A);
  return s;
}

// A p against central differences of Phi's gradient along a random p, body by body.
void expect_hessian_by_differences(const Assembled& s, const StepForm& form, const std::string& what) {
  const double eps = 1e-7;
  const Model& m = s.model;
  const Eigen::VectorXd& w = s.state.inv_mass;
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, m.num_bodies()), Ap, gp, gm, y;
  for (int b = 0; b < m.num_bodies(); ++b)
    if (w[b] == 0.0) p.col(b).setZero();  // the filtered subspace: dv = 0 there
  multiply(s.A, p, Ap);
  step_potential(m, s.state, form, s.start_length, s.dv + eps * p, y, gp);
  step_potential(m, s.state, form, s.start_length, s.dv - eps * p, y, gm);
  const Eigen::Matrix3Xd expected = (gp - gm) / (2 * eps);
  for (int b = 0; b < m.num_bodies(); ++b) {
    if (w[b] == 0.0) continue;
    EXPECT_LT((Ap.col(b) - expected.col(b)).norm(), 1e-6 * (1.0 + expected.col(b).norm())) << "body " << b << " " << what;
  }
}

TEST(SparseSystem, ExactMatrixIsTheHessianOfTheStepPotentialByFiniteDifferences) {
  for (const double scale : {1.1, 0.9}) {
    const double h = 0.01;
    Assembled s = assemble(scale, h, /*project=*/false);
    expect_hessian_by_differences(s, h, "scale " + std::to_string(scale));
  }
}

TEST(SparseSystem, AFamilyFormsMatrixIsTheHessianOfItsPotentialByFiniteDifferences) {
  // h_e, the dampers' step and the drag's factor apart (step_form.h), reference lengths not l_n.
  const double h = 0.01;
  const StepForm form(h, 1.6 * h, h / 1.6);
  Assembled s = assemble(1.1, h, /*project=*/false);
  for (double& l : s.start_length) l *= 0.98;
  Eigen::Matrix3Xd r;
  step_potential(s.model, s.state, form, s.start_length, s.dv, s.y, r);
  assemble_step_hessian(s.model, s.state.inv_mass, form, s.start_length, s.y, HessianBlocks::Exact, s.A);
  expect_hessian_by_differences(s, form, "family form");
}

TEST(SparseSystem, MatrixIsSymmetricExactOrProjected) {
  for (const bool project : {false, true}) {
    const Assembled s = assemble(0.9, 0.05, project);
    const Eigen::MatrixXd D = dense(s.A);
    EXPECT_LT((D - D.transpose()).norm(), 1e-12 * D.norm());
  }
}

TEST(SparseSystem, ImmovableBodiesAreFilteredOutOfTheSystem) {
  const Assembled s = assemble(1.1, 0.01, false);
  const Eigen::MatrixXd D = dense(s.A);
  for (int b = 0; b < s.model.num_bodies(); ++b) {
    if (s.state.inv_mass[b] != 0.0) continue;
    // Identity on its own block, nothing coupling it to anyone: the solve leaves dv_b = 0.
    EXPECT_EQ(D.block(3 * b, 3 * b, 3, 3), Eigen::Matrix3d::Identity());
    EXPECT_DOUBLE_EQ(D.block(3 * b, 0, 3, D.cols()).norm(), std::sqrt(3.0));
  }
}

TEST(SparseSystem, DynamicSphereBlockIsItsMassAlone) {
  const Assembled s = assemble(1.1, 0.01, false);
  const int sphere = s.model.sphere_body(0);
  const Eigen::MatrixXd D = dense(s.A);
  EXPECT_TRUE(D.block(3 * sphere, 3 * sphere, 3, 3).isApprox(2.0 * Eigen::Matrix3d::Identity()));
  EXPECT_NEAR(D.block(3 * sphere, 0, 3, D.cols()).norm(), 2.0 * std::sqrt(3.0), 1e-12);
}

// Where the matrix keeps a float copy (ImplicitDef::single_from), the assembly writes the
// copy's R itself: M + h c I, I at the pinned corners, less the springs to them at their
// neighbours. It is the R the sum over the springs gives (D + the blocks at each particle:
// refresh_copies), to float's rounding, exact or projected, the dynamic sphere's block included.
TEST(SparseSystem, TheAssemblysFloatRestIsDPlusTheBlocksAtEachParticle) {
  for (const bool project : {false, true}) {
    SCOPED_TRACE(project ? "projected" : "exact");
    Assembled s = assemble(0.9, 0.05, project);
    s.model.implicit.single_from = 0;
    build_pattern(s.model, s.A);
    assemble_step_hessian(s.model, s.state.inv_mass, 0.05, s.start_length, s.y,
                          project ? HessianBlocks::Projected : HessianBlocks::Exact, s.A);
    ASSERT_NE(s.A.refresh_single_copy, nullptr);
    const std::vector<float> written = s.A.single.rest_soa;
    s.A.refresh_copies();  // R as D + the blocks summed at each particle
    const std::vector<float>& summed = s.A.single.rest_soa;
    const int B = s.model.num_bodies();
    ASSERT_EQ(written.size(), 6u * B);
    ASSERT_EQ(summed.size(), 6u * B);
    // The movable ends of springs to the pinned corners: where R is not M + h c I.
    const Eigen::VectorXd& w = s.state.inv_mass;
    const Springs& springs = s.model.springs;
    std::vector<char> by_pin(B, 0);
    for (std::size_t k = 0; k < springs.size(); ++k) {
      const int a = springs.a[k], b = springs.b[k];
      if ((w[a] == 0.0) != (w[b] == 0.0)) by_pin[w[a] == 0.0 ? b : a] = 1;
    }
    int near_pins = 0;
    for (int b = 0; b < B; ++b) {
      double size = 0.0;
      for (int e = 0; e < 3; ++e) size = std::max(size, std::abs(double(summed[e * B + b])));
      for (int e = 0; e < 6; ++e)
        EXPECT_LE(std::abs(double(written[e * B + b]) - double(summed[e * B + b])), 1e-6 * size)
            << "body " << b << " entry " << e;
      if (!by_pin[b]) continue;
      ++near_pins;  // the springs to the pins taken out: R's diagonal is not the mass term's
      const double base = 1.0 / w[b] + 0.05 * s.model.air_drag;
      EXPECT_GT(std::abs(double(written[b]) - base), 1e-4 * size) << "body " << b;
    }
    EXPECT_GT(near_pins, 0);  // the case is there
  }
}

TEST(SparseSystem, ProjectionKeepsTheMatrixPositiveDefiniteAtHugeSteps) {
  // Every spring at 60% of its rest length and h = 1 s: the exact transverse stiffness
  // (tension / l < 0) makes the Hessian indefinite; projected, it is SPD.
  const Assembled exact = assemble(0.6, 1.0, false);
  const Assembled projected = assemble(0.6, 1.0, true);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e_exact(dense(exact.A));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e_projected(dense(projected.A));
  EXPECT_LT(e_exact.eigenvalues().minCoeff(), 0.0);
  EXPECT_GT(e_projected.eigenvalues().minCoeff(), 0.0);
}

TEST(SparseSystem, ThePreconditionerIsTheProjectedDiagonalsInverseEitherWay) {
  // So it stays SPD even where the exact matrix is not.
  const Assembled exact = assemble(0.6, 1.0, false);
  const Assembled projected = assemble(0.6, 1.0, true);
  for (int b = 0; b < exact.A.num_bodies(); ++b) {
    EXPECT_TRUE((exact.A.diag_inverse[b] * projected.A.diag[b]).isIdentity(1e-9)) << "body " << b;
    const Eigen::SelfAdjointEigenSolver<Mat3> e(exact.A.diag_inverse[b]);
    EXPECT_GT(e.eigenvalues().minCoeff(), 0.0);
  }
}

// A solver preconditioning with the sparse factor skips the 3x3 inverses; inverting the
// diagonal afterwards gives what the full assembly gives, to the bit.
TEST(SparseSystem, TheBlockJacobiInverseCanBeFormedLater) {
  Assembled s = assemble(0.6, 1.0, false);
  const std::vector<Mat3> full = s.A.diag_inverse;
  std::fill(s.A.diag_inverse.begin(), s.A.diag_inverse.end(), Mat3::Zero());
  assemble_step_hessian(s.model, s.state.inv_mass, 1.0, s.start_length, s.y, HessianBlocks::Exact, s.A, JacobiInverse::Skip);
  for (const Mat3& d : s.A.diag_inverse) EXPECT_TRUE(d.isZero(0.0));  // left as it was
  invert_diagonal(s.A);
  for (int b = 0; b < s.A.num_bodies(); ++b) EXPECT_EQ(s.A.diag_inverse[b], full[b]) << "body " << b;
}

TEST(SparseSystem, EitherAssemblyCarriesTheProjectedBlocksForTheFactor) {
  // The sparse factor (cholesky_preconditioner.h) is built from diag_projected / off_projected
  // after an exact assembly: they must be what a projected assembly puts in diag / off.
  const Assembled exact = assemble(0.6, 1.0, false);
  const Assembled projected = assemble(0.6, 1.0, true);
  for (int b = 0; b < exact.A.num_bodies(); ++b) {
    EXPECT_TRUE(exact.A.diag_projected[b].isApprox(projected.A.diag[b], 1e-14)) << "body " << b;
    EXPECT_TRUE(projected.A.diag_projected[b].isApprox(projected.A.diag[b], 1e-14)) << "body " << b;
  }
  for (std::size_t s = 0; s < exact.A.num_springs(); ++s)
    EXPECT_TRUE(exact.A.off_projected(s).isApprox(projected.A.off(s), 1e-14) ||
                (exact.A.off_projected(s) - projected.A.off(s)).norm() < 1e-12)
        << "spring " << s;
}

TEST(SparseSystem, StretchedSpringsNeedNoProjection) {
  // Every spring longer than its rest length and than at the start of the step: every
  // tension positive (moving at random, a damper can be shortening, and then it pushes; a
  // pinned corner would stay put while its neighbours move out past it).
  const Assembled exact = assemble(1.2, 1.0, false, /*moving=*/false, {"cloth.pinned=none"});
  const Assembled projected = assemble(1.2, 1.0, true, /*moving=*/false, {"cloth.pinned=none"});
  EXPECT_TRUE(dense(exact.A).isApprox(dense(projected.A), 1e-14));
}

}  // namespace
}  // namespace clothsim::testing
