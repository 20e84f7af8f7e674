// The sparse factor is exactly the inverse of the matrix it claims (S P S + (I - S), P the
// projected Hessian), checked against a dense copy built independently here; PCG preconditioned
// by the factor of its own matrix converges in one iteration; the cost estimates order as the
// measurements do; its SIMD kernels (block_factor_kernels.h) give the same bits on every
// Highway target this CPU runs.
#include "core/linear/cholesky_preconditioner.h"

#include <gtest/gtest.h>

#include <hwy/targets.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "test_support.h"
#include "core/implicit/sparse_system.h"
#include "core/implicit/step_potential.h"
#include "core/kernel_test_support.h"
#include "core/linear/conjugate_gradient.h"
#include "core/model/state.h"
#include "scene/build_model.h"

namespace clothsim::testing {
namespace {

// A compressed, moving 5 x 4 sheet with every spring type, two pinned corners and a dynamic
// sphere, at a step large enough (h^2 k / m ~ 500) that the projection matters.
struct Compressed {
  Model model;
  SpringBlockMatrix A;
  Eigen::Matrix3Xd b;
};

Compressed compressed_sheet(double h = 0.05) {
  Compressed s{model_from_yaml(R"(
name: sheet
cloth:
  particles: [5, 4]
  size: [1, 1]
  particle_mass: 0.1
  pinned: corners
  springs:
    structural: {stiffness: 20000, damping: 5}
    shear: {stiffness: 10000, damping: 3}
    bend: {stiffness: 1000, damping: 1}
spheres:
  - {center: [0, -2, 0], radius: 0.5, kinematic: false, mass: 2}
)"), {}, {}};
  State st = initial_state(s.model);
  std::srand(5);
  const int B = s.model.num_bodies();
  st.x += 0.01 * Eigen::Matrix3Xd::Random(3, B);
  std::vector<double> start_length;
  step_lengths(s.model, st.x, start_length);
  build_pattern(s.model, s.A);
  assemble_step_hessian(s.model, st.inv_mass, h, start_length, 0.7 * st.x, HessianBlocks::Exact, s.A);
  s.b = Eigen::Matrix3Xd::Random(3, B);
  for (int i = 0; i < B; ++i)
    if (st.inv_mass[i] == 0.0) s.b.col(i).setZero();
  return s;
}

// Dense (3B x 3B) S P S + (I - S) from the projected blocks.
Eigen::MatrixXd dense_filtered(const SpringBlockMatrix& A, const VelocityFilter& filter) {
  const int B = A.num_bodies();
  std::vector<Mat3> S(B, Mat3::Identity());
  for (std::size_t c = 0; c < filter.size(); ++c)
    S[filter.body[c]] -= filter.normal[c] * filter.normal[c].transpose();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * B, 3 * B);
  for (int i = 0; i < B; ++i)
    K.block<3, 3>(3 * i, 3 * i) = S[i] * A.diag_projected[i] * S[i] + Mat3::Identity() - S[i];
  for (std::size_t s = 0; s < A.num_springs(); ++s) {
    const int a = A.a[s], b = A.b[s];
    K.block<3, 3>(3 * a, 3 * b) += S[a] * A.off_projected(s) * S[b];
    K.block<3, 3>(3 * b, 3 * a) += S[b] * A.off_projected(s) * S[a];
  }
  return K;
}

Eigen::Map<const Eigen::VectorXd> flat(const Eigen::Matrix3Xd& m) { return {m.data(), m.size()}; }

TEST(CholeskyPreconditioner, InvertsTheProjectedMatrix) {
  const Compressed s = compressed_sheet();
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  ASSERT_TRUE(factor.factorize(s.A, VelocityFilter{}));
  Eigen::Matrix3Xd z;
  factor.apply(s.b, z);
  const Eigen::VectorXd residual = dense_filtered(s.A, {}) * flat(z) - flat(s.b);
  EXPECT_LE(residual.norm(), 1e-10 * s.b.norm());
}

TEST(CholeskyPreconditioner, AFactorPastTheBudgetIsKnownWithoutOrderingAndNeverBuilt) {
  const Compressed s = compressed_sheet();
  CholeskyPreconditioner full;
  full.analyse(s.A);
  // Its least size: one block per distinct pair of A (every spring of the sheet joins its
  // own pair), one D block per body.
  const std::size_t pairs = s.A.num_springs();
  ASSERT_GE(full.factor_blocks(), pairs);
  const std::size_t least = pairs * (sizeof(Mat3) + sizeof(int)) + s.A.num_bodies() * sizeof(Mat3);
  ASSERT_GT(full.factor_bytes(), least);  // fill, and the slack

  CholeskyPreconditioner capped;
  capped.analyse(s.A, least - 1);  // below even the factor without fill
  EXPECT_TRUE(capped.analysed());
  EXPECT_EQ(capped.factor_blocks(), pairs);
  EXPECT_GT(capped.factor_bytes(), least - 1);  // what a caller compares with its budget
  EXPECT_TRUE(std::isinf(capped.factor_cost()));
  EXPECT_FALSE(capped.ready());

  // Within the budget it is the full analysis.
  CholeskyPreconditioner within;
  within.analyse(s.A, full.factor_bytes());
  EXPECT_EQ(within.factor_blocks(), full.factor_blocks());
  EXPECT_EQ(within.factor_cost(), full.factor_cost());
}

TEST(CholeskyPreconditioner, TwoSpringsOnOnePairAreOneBlockOfItsLeastSize) {
  Compressed s = compressed_sheet();
  const std::size_t pairs = s.A.num_springs();
  s.A.a.push_back(s.A.b[0]);  // a second spring on the first pair, the other way round
  s.A.b.push_back(s.A.a[0]);
  CholeskyPreconditioner capped;
  capped.analyse(s.A, 0);
  EXPECT_EQ(capped.factor_blocks(), pairs);
}

TEST(CholeskyPreconditioner, HeldNormalsAreTheIdentityAndTheRestIsFiltered) {
  const Compressed s = compressed_sheet();
  VelocityFilter filter;
  filter.body = {3, 7, 8};
  filter.normal = {Vec3(0, 1, 0), Vec3(1, 1, 0).normalized(), Vec3(0.2, 0.3, -1).normalized()};
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  ASSERT_TRUE(factor.factorize(s.A, filter));
  Eigen::Matrix3Xd z;
  factor.apply(s.b, z);
  const Eigen::MatrixXd K = dense_filtered(s.A, filter);
  EXPECT_LE((K * flat(z) - flat(s.b)).norm(), 1e-10 * s.b.norm());
  // Along a held normal the matrix is the identity: z's normal component is b's.
  for (std::size_t c = 0; c < filter.size(); ++c) {
    const int i = filter.body[c];
    EXPECT_NEAR(filter.normal[c].dot(z.col(i)), filter.normal[c].dot(s.b.col(i)), 1e-12);
  }
  // A second factorisation, after the filter is gone, is of the unfiltered matrix again.
  ASSERT_TRUE(factor.factorize(s.A, VelocityFilter{}));
  factor.apply(s.b, z);
  EXPECT_LE((dense_filtered(s.A, {}) * flat(z) - flat(s.b)).norm(), 1e-10 * s.b.norm());
}

TEST(CholeskyPreconditioner, PreconditionsItsOwnMatrixToOneIteration) {
  Compressed s = compressed_sheet();
  // Solve with the projected matrix itself, whose factor is exact.
  s.A.use_projected();
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  ASSERT_TRUE(factor.factorize(s.A, VelocityFilter{}));
  Eigen::Matrix3Xd x, Ax;
  CgBuffers buffers;
  const CgResult jacobi = solve_pcg(s.A, s.b, x, CgSettings{500, 1e-10}, buffers);
  const CgResult factored = solve_pcg(s.A, s.b, x, CgSettings{500, 1e-10}, buffers, nullptr, &factor);
  EXPECT_TRUE(factored.converged);
  EXPECT_EQ(factored.iterations, 1);
  EXPECT_GT(jacobi.iterations, 10);  // what the factor saves at this step
  multiply(s.A, x, Ax);
  EXPECT_LE((s.b - Ax).norm(), 1e-9 * s.b.norm());
}

TEST(CholeskyPreconditioner, AFactorOfAnEarlierMatrixStillGivesTheExactSolution) {
  // A stale factor changes only the iteration count: PCG still solves the current system.
  const Compressed earlier = compressed_sheet(0.02);
  Compressed now = compressed_sheet(0.05);
  now.A.use_projected();
  CholeskyPreconditioner factor;
  factor.analyse(earlier.A);
  ASSERT_TRUE(factor.factorize(earlier.A, VelocityFilter{}));
  Eigen::Matrix3Xd x, Ax;
  CgBuffers buffers;
  const CgResult r = solve_pcg(now.A, now.b, x, CgSettings{500, 1e-10}, buffers, nullptr, &factor);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.iterations, 1);
  multiply(now.A, x, Ax);
  EXPECT_LE((now.b - Ax).norm(), 1e-9 * now.b.norm());
}

TEST(CholeskyPreconditioner, CostsMoreToBuildThanToApplyAndApplyingCostsMoreThanJacobi) {
  const Compressed s = compressed_sheet();
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  EXPECT_GT(factor.solve_cost(), 1.0);  // in block-Jacobi iterations
  EXPECT_GT(factor.factor_cost(), factor.solve_cost());
}

// A factor too large for the cache is costed by the bytes its solve streams (two passes over
// L, 76 bytes a block) against an iteration's (about 48 a spring and 150 a body): on the
// drape's 64 x 64 sheet (L about 31 MB) that is 2.3 times the multiply-adds' count, as the
// clock had it (BENCHMARKS.md); a 24 x 24 sheet's L fits, and its solve keeps the count.
TEST(CholeskyPreconditioner, CostsASolveOutOfCacheByTheBytesItStreams) {
  const auto analysed = [](int n) {
    const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                               {"cloth.particles=[" + std::to_string(n) + "," + std::to_string(n) + "]"}));
    SpringBlockMatrix A;
    build_pattern(model, A);
    const State st = initial_state(model);
    std::vector<double> length;
    step_lengths(model, st.x, length);
    assemble_step_hessian(model, st.inv_mass, 1.0 / 60.0, length, st.x, HessianBlocks::Projected, A);
    CholeskyPreconditioner factor;
    factor.analyse(A);
    const double bytes = 152.0 * static_cast<double>(factor.factor_blocks()) /
                         (48.0 * static_cast<double>(A.num_springs()) + 150.0 * A.num_bodies());
    return std::pair{factor.solve_cost(), bytes};
  };
  const auto [large, large_bytes] = analysed(64);
  EXPECT_DOUBLE_EQ(large, large_bytes);
  const auto [small, small_bytes] = analysed(24);
  EXPECT_LT(small, small_bytes);  // in cache: the count, below what the bytes would say
  EXPECT_GT(small, 1.0);
}

// The bodies are ordered to reduce fill: on a 25 x 25 sheet with bending springs (reaching two
// rows), the row-by-row order fills its band, 29,446 blocks of L (47 a column), and the inverse
// of AMD's permutation (the convention taken the wrong way round) 49,826; AMD's takes 17,032.
TEST(CholeskyPreconditioner, OrdersTheBodiesToReduceFill) {
  const Model model = model_from_yaml(R"(
name: sheet
cloth:
  particles: [25, 25]
  size: [1, 1]
  particle_mass: 0.1
  springs:
    structural: {stiffness: 20000, damping: 5}
    shear: {stiffness: 10000, damping: 3}
    bend: {stiffness: 1000, damping: 1}
)");
  const State st = initial_state(model);
  std::vector<double> start_length;
  step_lengths(model, st.x, start_length);
  SpringBlockMatrix A;
  build_pattern(model, A);
  assemble_step_hessian(model, st.inv_mass, 0.05, start_length, st.x, HessianBlocks::Projected, A);
  CholeskyPreconditioner factor;
  factor.analyse(A);
  EXPECT_LT(factor.factor_blocks(), 625u * 30u);
  Eigen::Matrix3Xd b = Eigen::Matrix3Xd::Random(3, 625), z;
  ASSERT_TRUE(factor.factorize(A, VelocityFilter{}));
  factor.apply(b, z);
  EXPECT_LE((dense_filtered(A, {}) * flat(z) - flat(b)).norm(), 1e-10 * b.norm());
}

// A non-finite matrix is refused, and the next factorisation of a good one is exact (nothing of
// the failed one is left in the factor's scratch).
TEST(CholeskyPreconditioner, ANonFiniteMatrixIsRefusedAndLeavesNothingBehind) {
  Compressed s = compressed_sheet();
  CholeskyPreconditioner factor;
  factor.analyse(s.A);
  SpringBlockMatrix bad = s.A;
  bad.alpha_projected[bad.slot[3]] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(factor.factorize(bad, VelocityFilter{}));
  EXPECT_FALSE(factor.ready());
  ASSERT_TRUE(factor.factorize(s.A, VelocityFilter{}));
  Eigen::Matrix3Xd z;
  factor.apply(s.b, z);
  EXPECT_LE((dense_filtered(s.A, {}) * flat(z) - flat(s.b)).norm(), 1e-10 * s.b.norm());
}

// The factor's kernels use no fused multiply-add and the same per-lane order at any vector
// width, so SCALAR, SSE4, AVX2 and AVX-512 factor and solve to the same bits (with held
// contacts, so the filtered blocks are in it too), and so does a run.
TEST(CholeskyPreconditioner, EveryTargetFactorsAndSolvesToTheSameBits) {
  const Compressed s = compressed_sheet();
  VelocityFilter filter;
  filter.body = {3, 7};
  filter.normal = {Vec3(0, 1, 0), Vec3(1, 1, 0).normalized()};
  const auto solve = [&] {
    CholeskyPreconditioner factor;
    factor.analyse(s.A);
    EXPECT_TRUE(factor.factorize(s.A, filter));
    Eigen::Matrix3Xd z;
    factor.apply(s.b, z);
    return z;
  };
  const Eigen::Matrix3Xd best = solve();
  EXPECT_LE((dense_filtered(s.A, filter) * flat(best) - flat(s.b)).norm(), 1e-10 * s.b.norm());
  const std::string names = for_each_highway_target([&](const char* target) {
    const Eigen::Matrix3Xd z = solve();
    EXPECT_EQ(0, std::memcmp(z.data(), best.data(), sizeof(double) * z.size())) << target;
  });
  ASSERT_FALSE(names.empty());
  RecordProperty("targets", names);
}

}  // namespace
}  // namespace clothsim::testing
