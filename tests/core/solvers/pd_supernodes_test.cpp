#include "core/solvers/pd_supernodes.h"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>

#include "pd_test_factors.h"

namespace clothsim::testing {
namespace {

using SparseL = Eigen::SparseMatrix<double>;

Supernodes supernodes_of(const SparseL& L, const Eigen::VectorXd& D, double share) {
  return clothsim::supernodes_of(static_cast<std::size_t>(L.cols()), L.outerIndexPtr(), L.innerIndexPtr(),
                                 L.valuePtr(), D.data(), share);
}

Supernodes supernodes_of(const PdFactor& f, double share) {
  return supernodes_of(f.ldlt.matrixL().nestedExpression(), f.ldlt.vectorD(), share);
}

std::size_t width(const Supernodes& f, std::size_t s) { return f.first[s + 1] - f.first[s]; }
std::size_t height(const Supernodes& f, std::size_t s) { return f.row_start[s + 1] - f.row_start[s]; }

// Entries of supernode s's panel strictly below the diagonal, zeros included.
std::size_t panel_lower(const Supernodes& f, std::size_t s) {
  const std::size_t w = width(f, s);
  return w * (w - 1) / 2 + (height(f, s) - w) * w;
}

// L (unit diagonal left out) rebuilt from the panels.
Eigen::MatrixXd dense_lower(const Supernodes& f) {
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(f.n, f.n);
  for (std::size_t s = 0; s < f.size(); ++s) {
    const std::size_t w = width(f, s);
    for (std::size_t i = 0; i < height(f, s); ++i)
      for (std::size_t k = 0; k < w; ++k) {
        const std::size_t row = f.rows[f.row_start[s] + i], col = f.first[s] + k;
        if (row > col) L(row, col) = f.value[f.value_start[s] + i * w + k];
      }
  }
  return L;
}

TEST(PdSupernodes, ADenseFactorIsOneSupernode) {
  const int n = 6;
  Eigen::MatrixXd A = Eigen::MatrixXd::Constant(n, n, 1.0) + n * Eigen::MatrixXd::Identity(n, n);
  Eigen::SimplicialLDLT<SparseL, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt(A.sparseView());
  const Supernodes f = supernodes_of(ldlt.matrixL().nestedExpression(), ldlt.vectorD(), 0.0);
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(width(f, 0), 6u);
  EXPECT_EQ(panel_lower(f, 0), f.entries);
}

TEST(PdSupernodes, FundamentalSupernodesStoreNoZeros) {
  DrapeFactor drape(25);
  const Supernodes f = supernodes_of(drape.pd(), 0.0);
  std::size_t stored = 0;
  for (std::size_t s = 0; s < f.size(); ++s) stored += panel_lower(f, s);
  EXPECT_EQ(stored, f.entries);
  EXPECT_LT(f.size(), f.n / 2);  // AMD's separators make wide ones
}

TEST(PdSupernodes, RelaxedPanelsKeepTheirZerosWithinTheShareAndAreFewer) {
  DrapeFactor drape(25);
  const PdFactor& pd = drape.pd();
  const Eigen::MatrixXd L = SparseL(pd.ldlt.matrixL().nestedExpression()).toDense();
  for (double share : {0.1, 0.3}) {
    const Supernodes f = supernodes_of(pd, share);
    const Eigen::MatrixXd rebuilt = dense_lower(f);
    for (std::size_t s = 0; s < f.size(); ++s) {
      const Eigen::Index c0 = f.first[s], w = static_cast<Eigen::Index>(width(f, s));
      const auto stored_nonzeros = (rebuilt.middleCols(c0, w).array() != 0.0).count();
      EXPECT_LE(static_cast<double>(panel_lower(f, s)) - static_cast<double>(stored_nonzeros),
                share * static_cast<double>(panel_lower(f, s)) + 1e-9)
          << "share " << share << ", supernode " << s;
    }
    EXPECT_LT(f.size(), supernodes_of(pd, 0.0).size()) << share;
    EXPECT_TRUE(rebuilt == L) << share;  // every entry of L in its panel, nothing else
  }
}

}  // namespace
}  // namespace clothsim::testing
