// Projective dynamics' global solve, L D L^T z = b for the three columns at once, in SIMD:
// each body's row padded to four lanes (x, y, z, 0), so an entry of L costs one vector
// multiply and add on AVX2 and AVX-512 instead of three scalar ones. Both substitutions
// gather: the forward one walks L by rows (a copy in compressed rows), the backward one by
// columns, so each row of z is stored once rather than once per entry. Every target runs the
// same operations in the same order per lane, so gives the same bits.
#pragma once

#include <cstddef>

namespace clothsim {

// A unit lower triangular L (strictly lower entries stored) twice, and the n pivots of D.
struct LowerFactor {
  std::size_t n = 0;
  const int* row_start;     // (n + 1) by rows: row j's entries at [row_start[j], row_start[j + 1])
  const int* row_col;       // their columns
  const double* row_value;
  const int* col_start;     // (n + 1) by columns
  const int* col_row;       // their rows
  const double* col_value;
  const double* pivot;      // (n)
};

// z4 (4 x n, column-major, lane 3 ignored) <- (L D L^T)^-1 z4.
void ldlt_solve_padded(const LowerFactor& f, double* z4);

}  // namespace clothsim
