// Projective dynamics' global solve, L D L^T z = b for the three columns at once, in SIMD:
// each body's row padded to four lanes (x, y, z, 0), so an entry of L costs one vector
// multiply and subtract (forward, by columns of L) or multiply and add (backward, by rows of
// L^T) on AVX2 and AVX-512 instead of three scalar ones. Operations and their order are the
// scalar sweep's, so every target gives the same bits.
#pragma once

#include <cstddef>

namespace clothsim {

// z4 (4 x n, column-major, lane 3 ignored) <- (L D L^T)^-1 z4, with L strictly lower in
// compressed columns (start: n + 1 column starts; row, value: its entries; unit diagonal
// implied) and d its n pivots.
void ldlt_solve_padded(const int* start, const int* row, const double* value, const double* d, std::size_t n,
                       double* z4);

}  // namespace clothsim
