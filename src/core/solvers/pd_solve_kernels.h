// Projective dynamics' global solve, L D L^T z = b for the three columns at once, in SIMD:
// each body's row padded to four lanes (x, y, z, 0), so an entry of L costs one vector
// multiply and add on AVX2 and AVX-512 instead of three scalar ones. L is read by supernodes
// (pd_supernodes.h), a few columns at a time: forward, their solved rows of z stay in
// registers while each panel row below is updated from contiguous values and stored once;
// backward, each panel row below is loaded once for all of those columns. In float (PD's
// panels, pd_kernels.h) a padded row is half a 256-bit vector, so AVX2 updates two panel rows
// per vector. Every target runs the same operations in the same order per lane, so gives the
// same bits (per value type).
#pragma once

#include "pd_supernodes.h"

namespace clothsim {

// z4 (4 x n, column-major, lane 3 ignored) <- (L D L^T)^-1 z4.
void ldlt_solve_padded(const Supernodes& f, double* z4);
// The same in float, for a factor that only corrects a residual taken in double.
void ldlt_solve_padded(const SupernodesF& f, float* z4);

}  // namespace clothsim
