// Preconditioned conjugate gradient on a SpringBlockMatrix (Shewchuk, "An Introduction to
// the Conjugate Gradient Method Without the Agonizing Pain", 1994, B3), with the block-Jacobi
// preconditioner: the inverse of each body's 3x3 diagonal block. Mass dominates those blocks
// at small steps (CG then converges in a few iterations); the preconditioner also removes
// the spread of masses between cloth particles and heavy dynamic spheres.
#pragma once

#include <Eigen/Core>

#include "integrators/sparse_system.h"

namespace clothsim {

// Scratch vectors (3 x B), kept by the caller so a solve allocates nothing.
struct CgBuffers {
  Eigen::Matrix3Xd r, z, p, q;
};

struct CgResult {
  int iterations = 0;
  double relative_residual = 0.0;  // |b - A x| / |b| as CG's recurrence tracks it
  bool converged = true;           // false: hit max_iterations above tolerance, or A not SPD
};

struct CgSettings {
  int max_iterations = 200;
  double tolerance = 1e-8;          // stop when |b - A x| <= tolerance |b| ...
  double absolute_tolerance = 0.0;  // ... or |b - A x| <= this (the caller's accuracy need)
  bool from_guess = false;          // start from the x passed in (warm start) rather than 0
};

// Solves A x = b, stopping at either tolerance or after max_iterations.
CgResult solve_pcg(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, Eigen::Matrix3Xd& x,
                   const CgSettings& settings, CgBuffers& buffers);

}  // namespace clothsim
