// The spring force pass in SIMD, over a SpringLayout's grid-stencil families, through Google
// Highway with runtime dispatch: one binary carries the kernel for plain x86-64 (Highway's
// SCALAR target), SSSE3, SSE4, AVX2 and AVX-512 (AVX3) and runs the best one the CPU supports
// (chosen at the first call).
//
// Per evaluation: the positions are walked in blocks (2048), every family in turn within a
// block. A block copies the particles it reads from x and v (3 x B) into structure-of-arrays
// scratch (xs, ys, zs, ...), runs each family over its positions p in vectors of L lanes with
// contiguous unaligned loads of p .. p+L-1 and of p+offset .. p+offset+L-1 (no gathers: they
// ran slower than scalar code on the project's machine), adds the force on a into one SoA sum
// at p and subtracts it from a second one at p + offset (no two lanes of a store share a
// particle, and a pass never stores where its next load overlaps), then adds the particles it
// finished into f. The scratch is a window of about 2048 + 2 nx particles that slides with the
// blocks, so it stays in cache on any grid.
//
// Numerics. Each spring's force is the scalar reference's (forces.h) to the bit: the same
// operations in the same order, no fused multiply-add (this file is compiled with
// -ffp-contract=off and calls Mul and Add, never MulAdd). Only the order in which a particle's
// spring forces are summed differs from the scalar pass ((block, family) order here, spring
// list order there), so the two agree to rounding (below 1e-15 relative to the largest spring
// force on the tests' states), not bit for bit. Because lanes never mix, no FMA is used and
// the blocks do not depend on the lane count, every target (SCALAR .. AVX3) gives the same
// bits: a run is bit-identical from run to run and across x86-64 CPUs. The largest strain is
// the exact maximum of the rounded l / l0 (a NaN length sticks), the same number as the scalar
// pass returns.
#pragma once

#include <Eigen/Core>

#include "spring_layout.h"
#include "core/base/body_terms.h"

namespace clothsim {

// f (3 x B, B >= layout.num_particles) += the spring-damper forces of the layout's families
// (not its `others`) at (x, v). Returns their largest l / l0 (1 when no spring is stretched, NaN
// when a length is NaN). Thread-safe: the scratch is per thread.
double accumulate_family_spring_forces(const SpringLayout& layout, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

// The same pass with each particle's body terms (body_terms.h) applied as the walk finishes it:
// f's columns [0, finished) are written, not added to (f need not be zeroed): the particles'
// spring forces then their body terms, bit for bit what accumulate_family_spring_forces into a
// zeroed f followed by body_terms() gives. Columns from `finished` on (particles no spring
// reaches, other bodies) are not touched. The layout's `others` are not run: for layouts
// without them. Saves the zeroing of f and a second pass over the bodies.
double family_forces_with_body_terms(const SpringLayout& layout, const Eigen::Matrix3Xd& x,
                                     const Eigen::Matrix3Xd& v, const BodyTermInputs& terms,
                                     Eigen::Matrix3Xd& f, std::size_t& finished);

// The Highway target the dispatcher runs on this CPU ("AVX3", "AVX2", "SSE4", ...).
const char* spring_kernel_target();

// The larger of two ratios, a NaN in either winning (how the passes combine their strains).
inline double sticky_max(double a, double b) {
  if (a != a) return a;
  return (b != b || b > a) ? b : a;
}

}  // namespace clothsim
