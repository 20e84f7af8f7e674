// The Newton matrix's assembly in SIMD over a SpringLayout's grid-stencil families (the
// implicit step's H = M + h c I - h^2 sum K_s, sparse_system.h), through Google Highway with
// runtime dispatch, in two passes:
//  1. over the springs, with the walk and window of the other spring passes
//     (spring_window-inl.h: contiguous loads of each spring's ends, no gathers): each block's u
//     and (alpha, beta), exact and projected, stored by slot;
//  2. over the particles: each diagonal block, M + h c I minus the blocks of the springs whose
//     a or whose b the particle is, read from their slots by particle (the slot order's gaps,
//     spring_layout.h, keep those reads inside a family's slots), family after family in a
//     fixed order, so no sums are scattered to both ends of a spring (a first version that
//     did, 24 sum arrays in the window, ran at half this speed at 64 x 64: their traffic).
// Each block is the scalar reference's (sparse_system.h, assemble_step_hessian_scalar) with u
// and T / l taken as products with one reciprocal 1 / l where the reference divides by l four
// times (one division instead of four: the divider bounds the pass), so the blocks agree with
// the reference's to an ulp or two, and the diagonal blocks to rounding (their sums run in
// another order). No fused multiply-add (this file is compiled with -ffp-contract=off), no
// mixing of lanes: every target (SCALAR .. AVX3) gives the same bits.
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "core/springs/spring_layout.h"

namespace clothsim {

// The families' Newton blocks at end-of-step positions y (3 x B): sparse_system.h's assembly
// of H = M + h c I - h^2 sum K_s for the springs of the families. Writes, by slot, each
// spring's u and its (alpha, beta), exact or projected per `project`, and the projected pair
// (zero where an end is immovable: the pair's block is removed); and the diagonal blocks of
// particles 0 .. F - 1 (F returned; particles from F on, which no spring reaches, are the
// caller's): (1 / w + drag_h drag) I minus the blocks of the families' springs there, the identity
// where w = 0; diag_projected likewise with the projected blocks (without `project`).
// start_length by slot; inv_mass (B).
struct FamilyHessian {
  double* ux;  // (slots) outputs
  double* uy;
  double* uz;
  double* alpha;
  double* beta;
  double* alpha_projected;
  double* beta_projected;
  double* diag;            // (9 B) column-major 3 x 3 blocks
  double* diag_projected;  // (9 B), unused with `project`
  double* diag_soa;        // (6 B) diag's blocks again, as SpringBlockMatrix::diag_soa
  // (6 B) where not null, R at the particles, as SpringBlockMatrix::single's rest_soa, from
  // M + h c I rather than D (the caller's when no other spring adds to D; terms added to D
  // later, as the barrier's, recompute R: SpringBlockMatrix::refresh_copies)
  float* rest_soa = nullptr;
  std::size_t bodies = 0;  // B
  double h = 0.0;          // s, the step (StepForm::h)
  double damper_h = 0.0;   // s, the dampers' step (StepForm::damper_h; h for backward Euler)
  double drag_h = 0.0;     // s, the drag term's (StepForm::drag_h; h for backward Euler)
  double drag = 0.0;       // N s / m, the particles' air drag c
  bool project = false;
};
std::size_t family_assemble(const SpringLayout& layout, const Eigen::Matrix3Xd& y,
                            const Eigen::VectorXd& inv_mass, const double* start_length,
                            const FamilyHessian& out);

// The part of the matrix that is not the families' spring coupling, R_i = D_i + the sum of the
// blocks G_s stored at particle i's family springs (sparse_system.h: D_i holds -G_s), from the
// double numbers (by slot; diag_soa: D as SpringBlockMatrix::diag_soa), in double, rounded to
// float into rest_soa (6 B, the same layout): mass, drag, contact terms, and the springs whose
// other end is immovable (stored as zero blocks). Bodies no spring reaches keep D. (The sum
// must be of the double blocks: with the float ones, R's rounding would be D's again.) Where
// D holds only the families' blocks, the assembly writes R without it (FamilyHessian::rest_soa).
void family_rest_diagonal(const SpringLayout& layout, const double* ux, const double* uy, const double* uz,
                          const double* alpha, const double* beta, const double* diag_soa, std::size_t bodies,
                          float* rest_soa);

// to[i] = from[i] rounded to float, i < n, in SIMD.
void demote_to_float(const double* from, std::size_t n, float* to);

}  // namespace clothsim
