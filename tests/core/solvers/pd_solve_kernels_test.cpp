#include "core/solvers/pd_solve_kernels.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "core/kernel_test_support.h"
#include "pd_test_factors.h"

namespace clothsim::testing {
namespace {

// b (free rows in the model's order) in the factor's row order, padded to four lanes.
Eigen::Matrix4Xd padded_rhs(const PdFactor& f, const Eigen::MatrixX3d& b) {
  Eigen::Matrix4Xd z = Eigen::Matrix4Xd::Zero(4, b.rows());
  for (std::size_t i = 0; i < f.row.size(); ++i)
    if (f.row[i] >= 0) z.col(f.row[i]).head<3>() = b.row(f.free_index[i]).transpose();
  return z;
}

// The supernodal solve against Eigen's on the drape's matrix, pins included, at panels of
// every kind: fundamental, the default's relaxed ones and wide ones storing many zeros.
TEST(PdSolveKernels, TheSupernodalSolveIsEigensSolveOnTheDrape) {
  for (int n : {9, 25, 40}) {
    DrapeFactor drape(n);
    const PdFactor& f = drape.pd();
    const auto& L = f.ldlt.matrixL().nestedExpression();
    const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(f.ldlt.rows(), 3);
    const Eigen::MatrixX3d expected = f.ldlt.solve(b);
    for (double share : {0.0, 0.3, 2.0}) {
      const Supernodes panels = supernodes_of(static_cast<std::size_t>(L.cols()), L.outerIndexPtr(),
                                              L.innerIndexPtr(), L.valuePtr(), f.ldlt.vectorD().data(), share);
      Eigen::Matrix4Xd z = padded_rhs(f, b);
      ldlt_solve_padded(panels, z.data());
      double worst = 0.0;
      for (std::size_t i = 0; i < f.row.size(); ++i)
        if (f.row[i] >= 0)
          worst = std::max(worst, (z.col(f.row[i]).head<3>() - expected.row(f.free_index[i]).transpose()).norm());
      EXPECT_LT(worst, 1e-12 * expected.cwiseAbs().maxCoeff()) << n << "x" << n << ", share " << share;
    }
  }
}

// A vector per padded row (AVX2, AVX-512), two lanes twice (SSE) or one lane thrice (SCALAR):
// the same operations in the same order, so the same bits, on panels up to 8 columns at once;
// on the float panels PD keeps (a 128-bit vector a row in float).
TEST(PdSolveKernels, TheSolveGivesTheSameBitsOnEveryHighwayTarget) {
  DrapeFactor drape(25);
  const PdFactor& f = drape.pd();
  const Eigen::Matrix3Xd b = random_field(static_cast<int>(f.ldlt.rows()), 5);
  Eigen::Matrix4Xf first;
  RecordProperty("targets", for_each_highway_target([&](const char* target) {
    Eigen::Matrix4Xf z = Eigen::Matrix4Xf::Zero(4, b.cols());
    z.topRows<3>() = b.cast<float>();
    ldlt_solve_padded(f.panels, z.data());
    if (first.size() == 0) first = z;
    EXPECT_TRUE(z.topRows<3>() == first.topRows<3>()) << target;
  }));
}

// The float panels (PD's, which only correct a residual taken in double) solve within float's
// accuracy of Eigen's double solve: the rounding of L, D and z leaves 1.4e-7 to 3.4e-7 of
// the answer at 9, 25 and 40 (a few float epsilons: the drape's matrix is well conditioned).
TEST(PdSolveKernels, TheFloatSolveIsEigensWithinFloatsAccuracy) {
  for (int n : {9, 25, 40}) {
    DrapeFactor drape(n);
    const PdFactor& f = drape.pd();
    const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(f.ldlt.rows(), 3);
    const Eigen::MatrixX3d expected = f.ldlt.solve(b);
    Eigen::Matrix4Xf z = padded_rhs(f, b).cast<float>();
    ldlt_solve_padded(f.panels, z.data());
    double worst = 0.0;
    for (std::size_t i = 0; i < f.row.size(); ++i)
      if (f.row[i] >= 0)
        worst = std::max(worst, (z.col(f.row[i]).head<3>().cast<double>() - expected.row(f.free_index[i]).transpose()).norm());
    const double relative = worst / expected.cwiseAbs().maxCoeff();
    char gap[32];
    std::snprintf(gap, sizeof gap, "%.2e", relative);
    RecordProperty("relative_gap_" + std::to_string(n), gap);
    EXPECT_LT(relative, 1e-5) << n << "x" << n;
    EXPECT_GT(relative, 1e-12) << "not a float solve";
  }
}

}  // namespace
}  // namespace clothsim::testing
