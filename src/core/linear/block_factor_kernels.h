// The sparse block factor's hot loops (cholesky_preconditioner.h) in SIMD, through Google
// Highway with runtime dispatch, as the spring force pass (spring_kernels.h).
//
// Blocks the kernels only read (L's and D^-1's) are stored compactly, column-major in 9
// doubles (as Eigen's Matrix3d, so the factor's memory is unchanged); blocks and vectors they
// write (the up-looking row's scratch Y, D_k, the solve's vector) are padded, a column or a
// 3-vector to 4 doubles. A column is then one 4-lane load, whose 4th lane is the next column's
// first entry: a lane whose results land only in the padding and are never read. So a block
// times a vector is three vector multiplies and two adds, c0 u0 + c1 u1 + c2 u2, and a block
// times a block three of those, with no shuffles and no gathers: the 3x3 products that Eigen's
// fixed-size code ran as 27 scalar multiply-adds each (the factorisation's inner loop and the
// factored solve's, 33 % and 25 % of implicit Euler's time on stiff.yaml at 1/60 s,
// BENCHMARKS.md) become 9 vector multiplies and 6 adds. The read-only arrays need 3 doubles
// of slack past their last block (kBlockSlack) for the last column's 4th lane.
//
// Numerics. Lanes never mix but in the transposed solve's three sums, whose lanes are added in
// a fixed order ((l0 + l1) + l2) after the loop, there is no fused multiply-add (the file is
// compiled with -ffp-contract=off and calls Mul, Add and Sub only), and each lane's operations
// come in the same order whatever the vector width (a target with 2 lanes runs a column as two
// halves). So every Highway target gives the same bits, as the spring pass does.
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace clothsim {

// Doubles per compact block (3 columns of 3), per padded block (3 columns of 4) and per
// padded vector; doubles of slack past a compact array's last block.
inline constexpr int kBlock = 9;
inline constexpr int kPaddedBlock = 12;
inline constexpr int kPaddedVector = 4;
inline constexpr int kBlockSlack = 3;

// The blocks of the factor L D L^T (cholesky_preconditioner.h): L unit lower triangular in
// 3x3 blocks by column, column j's blocks L(row[p], j) = value[p] for p in column_start[j] ..
// column_start[j + 1]; D's blocks inverted.
struct PaddedFactor {
  int bodies = 0;
  const int* column_start = nullptr;  // (B + 1)
  const int* row = nullptr;           // (blocks of L)
  const double* value = nullptr;      // (9 x blocks of L, + slack)
  const double* d_inverse = nullptr;  // (9 x B, + slack)
};

// Row k of the up-looking L D L^T (Davis 2005's ldl_numeric with 3x3 entries), after the
// caller has scattered A(i, k), i < k, into y and listed the row's pattern (the reach of
// column k up the elimination tree, in topological order) in pattern[0 .. count):
// for each i there, Y_i = y_i (then zeroed); y_r -= L(r, i) Y_i for the blocks of column i
// filled so far; L(k, i) = Y_i^T D_i^-1 is appended to column i (row k); d -= L(k, i) Y_i.
// y (12 x B, padded), value (9 per block) and row are written; filled (B) counts each
// column's blocks so far; d (12, padded) holds A(k, k) on entry and D_k on return;
// d_inverse (9 x B) holds D_i^-1 for the rows before k.
void factor_row(int k, const int* pattern, int count, double* y, const int* column_start,
                int* filled, int* row, double* value, const double* d_inverse, double* d);

// z = (L D L^T)^-1 r in the factor's order: r and z (3 x B) in the bodies' order, order[new] =
// old; w (4 x B) scratch.
void factor_solve(const PaddedFactor& factor, const int* order, const double* r, double* z,
                  double* w);

// The Highway target the factor's kernels run on ("AVX3", "AVX2", ...).
const char* block_factor_target();

}  // namespace clothsim
