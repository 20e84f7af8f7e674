// Preconditioned conjugate gradient on a SpringBlockMatrix (Shewchuk, "An Introduction to
// the Conjugate Gradient Method Without the Agonizing Pain", 1994, B3), with the block-Jacobi
// preconditioner: the inverse of each body's 3x3 diagonal block. Mass dominates those blocks
// at small steps (CG then converges in a few iterations); the preconditioner also removes
// the spread of masses between cloth particles and heavy dynamic spheres.
#pragma once

#include <Eigen/Core>
#include <limits>

#include "block_matrix.h"
#include "preconditioner.h"
#include "velocity_filter.h"

namespace clothsim {

// Scratch vectors (3 x B), kept by the caller so a solve allocates nothing.
struct CgBuffers {
  Eigen::Matrix3Xd r, z, p, q;
};

struct CgResult {
  int iterations = 0;
  double relative_residual = 0.0;  // |b - A x| / |b| as CG's recurrence tracks it
  bool converged = true;           // false: hit max_iterations above tolerance, or A not SPD
  bool negative_curvature = false; // stopped at a direction p with p^T A p <= 0 (x is the
                                   // iterate before it, or p itself if it was the first; with
                                   // a trust radius, the boundary along p)
  bool boundary = false;           // x was taken to the trust radius (Steihaug-Toint)
  double step_norm = 0.0;          // |x| in the trust region's norm (0: not measured)
  // q(x) = 1/2 x.A x - b.x at the answer (filtered: x.SAS x / 2 - Sb.x), by CG's recurrences
  // (each step lowers it by alpha r.z / 2): the model's value a trust region's ratio needs,
  // without another mat-vec.
  double model_value = 0.0;
};

struct CgSettings {
  int max_iterations = 200;
  double tolerance = 1e-8;          // stop when |b - A x| <= tolerance |b| ...
  double absolute_tolerance = 0.0;  // ... or |b - A x| <= this (the caller's accuracy need)
  bool from_guess = false;          // start from the x passed in (warm start) rather than 0
  double b_norm = -1.0;             // |b| where the caller has it (negative: solve_pcg takes it)
  // Steihaug-Toint: |x| stays within trust_radius; at negative curvature or where the next
  // iterate would leave, x goes to the boundary along p (Nocedal & Wright, Algorithm 7.2).
  // The norm is the preconditioner's, |x|_M = sqrt(x^T M x) (M^-1 the preconditioner; needs
  // a start from zero: from a guess the radius is not applied; the mass norm was measured and
  // lost, BENCHMARKS.md #37, round s34). Infinite: truncated CG as above.
  bool trust_region = false;        // measure |x| (CgResult::step_norm), and bound it by:
  double trust_radius = std::numeric_limits<double>::infinity();
};

// Solves A x = b, stopping at either tolerance, after max_iterations, or at the first
// direction of non-positive curvature (A indefinite: truncated CG, Nocedal & Wright,
// Algorithm 7.1). With a filter, solves S A S x = S b for x in the range of S (Baraff &
// Witkin's modified PCG): the residual, the preconditioned residual and A p are filtered, so
// x never moves along a held normal. The preconditioner is `pre` when given and ready (the
// sparse factor of cholesky_preconditioner.h or the V-cycle of multigrid_preconditioner.h),
// else block Jacobi (A.diag_inverse).
// Started from zero, every iterate x_k is a descent direction for the quadratic
// 0.5 x^T A x - b^T x's gradient at 0 (b . x_k > 0), whatever the iteration it stops at; at
// negative curvature on the first direction, x is that direction, the preconditioned
// residual (still b . x > 0), so the caller always has a step to take.
CgResult solve_pcg(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, Eigen::Matrix3Xd& x,
                   const CgSettings& settings, CgBuffers& buffers,
                   const VelocityFilter* filter = nullptr,
                   const Preconditioner* pre = nullptr);

}  // namespace clothsim
