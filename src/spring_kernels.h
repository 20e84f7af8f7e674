// The spring force pass in SIMD, over a SpringLayout's grid-stencil families, through Google
// Highway with runtime dispatch: one binary carries the kernel for SSE2 up to AVX-512 and
// runs the best one the CPU supports (chosen at the first call).
//
// Per evaluation: x and v are copied into structure-of-arrays scratch (xs, ys, zs, ...); each
// family is one pass over its positions p in vectors of L lanes, with contiguous unaligned loads
// of p .. p+L-1 and of p+offset .. p+offset+L-1 (no gathers: they ran slower than scalar code
// on the project's machine); the force on a is added to one SoA accumulator at p and
// subtracted from a second one at p + offset, so neither pass stores into lanes another lane of
// the same vector reads; both accumulators are added back into f (3 x B) at the end.
//
// Numerics. Each spring's force is the scalar reference's (forces.h) to the bit: the same
// operations in the same order, no fused multiply-add (this file is compiled with
// -ffp-contract=off and calls Mul and Add, never MulAdd). Only the order in which a particle's
// spring forces are summed differs from the scalar pass (family by family here, spring list
// order there), so the two agree to rounding (~1e-16 relative to the largest spring force),
// not bit for bit. Because lanes never mix and no FMA is used, every target (SSE2, SSE4,
// AVX2, AVX-512) gives the same bits: a run is bit-identical from run to run and across x86-64
// CPUs. The largest strain is the exact maximum of the rounded l / l0 (a NaN length sticks),
// the same number as the scalar pass returns.
#pragma once

#include <Eigen/Core>

#include "spring_layout.h"

namespace clothsim {

// f (3 x B, B >= layout.num_particles) += the spring-damper forces of the layout's families
// (not its `others`) at (x, v). Returns their largest l / l0 (1 when no spring is stretched, NaN
// when a length is NaN). Thread-safe: the scratch is per thread.
double accumulate_family_spring_forces(const SpringLayout& layout, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

// The Highway target the dispatcher runs on this CPU ("AVX3", "AVX2", "SSE4", ...).
const char* spring_kernel_target();

// The larger of two ratios, a NaN in either winning (how the passes combine their strains).
inline double sticky_max(double a, double b) {
  if (a != a) return a;
  return (b != b || b > a) ? b : a;
}

}  // namespace clothsim
