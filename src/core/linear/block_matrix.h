// The Newton matrix of one backward-Euler step as linear/ sees it: one 3x3 block per body on
// the diagonal and one per spring off it, stored by spring. implicit/sparse_system.h says what
// the blocks are and assembles them; the solvers of this floor (conjugate_gradient.h,
// cholesky_preconditioner.h) read them.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/springs/spring_force.h"   // Vec3, Mat3
#include "core/springs/spring_layout.h"

namespace clothsim {

struct SpringBlockMatrix;
// y = A p (3 x B). The floor that assembles A supplies it (implicit/sparse_system.h's multiply:
// the families in SIMD), so the solvers here need no kernels from above.
using BlockMultiply = void (*)(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y);

// A spring's block is a rank-one term plus a multiple of the identity (spring_force.h's
// K = axial u u^T + transverse (I - u u^T)), so it is stored as two numbers and u:
//     G_s = alpha_s u_s u_s^T + beta_s I
// (5 numbers instead of 9, and no 3x3 product to build or to apply: assembly 1.4-1.6 times
// faster, BENCHMARKS.md). Exact and projected blocks share u and differ only in
// (alpha, beta) across a compressed spring.
//
// The per-spring numbers are stored by the model's slot order (spring_layout.h), as
// structure of arrays, so the mat-vec runs the layout's families in SIMD with contiguous loads
// (potential_kernels.h); spring s's are at slot[s]. Slots without a spring hold zeros.
struct SpringBlockMatrix {
  BlockMultiply multiply = nullptr;  // y = A p: set with the pattern (build_pattern)
  std::vector<std::int32_t> a, b;  // (S) block (a_s, b_s): the springs' index pairs
  std::vector<std::int32_t> slot;  // (S) where spring s's numbers are stored
  // The layout the slots follow (the Model's, which outlives the matrix), or null: slots are
  // then spring order and every pass is scalar.
  const SpringLayout* layout = nullptr;
  std::vector<Mat3> diag;          // (B) diagonal blocks
  std::vector<double> ux, uy, uz;  // (slots) the spring's direction at the iterate
  std::vector<double> alpha, beta;  // (slots) block at (a_s, b_s); symmetric, so also at (b_s, a_s)
  // The projected matrix's blocks, filled either way: the preconditioners are built from them
  // (block Jacobi here, the sparse factor of cholesky_preconditioner.h), so they are SPD
  // whatever the matrix.
  std::vector<Mat3> diag_projected;                     // (B)
  std::vector<double> alpha_projected, beta_projected;  // (slots)
  std::vector<Mat3> diag_inverse;    // (B) the block-Jacobi preconditioner: diag_projected^-1
  // diag and diag_inverse again, as structure of arrays for the SIMD passes (the mat-vec's
  // diagonal, the Jacobi solve): entry e of body i's symmetric block at e B + i, entries xx,
  // yy, zz, xy, xz, yz. assemble_step_hessian and invert_diagonal write both forms; whoever
  // writes diag or the spring numbers otherwise calls refresh_copies().
  std::vector<double> diag_soa;          // (6 B)
  std::vector<double> diag_inverse_soa;  // (6 B)
  // On large sheets, the SIMD mat-vec's copy of the matrix in float: the families' spring
  // numbers by slot, and R_i = D_i + the blocks stored at i's family springs (the mass, drag
  // and contact terms, and the springs to immovable bodies) as diag_soa. The mat-vec applies
  // it as A p = R p + each spring's G_s (p_b - p_a) at a and its negative at b, in double.
  // It streams these numbers once per CG iteration, and on large sheets they do not fit a
  // core's cache: 21 bytes a slot instead of 48 (BENCHMARKS.md #37, round s37). Rounding a
  // spring's numbers scales its own block by 1 +- 2^-22 or so and, applied to the difference of
  // its ends, never touches rigid motions, so the rounded matrix is within that factor of A in
  // energy whatever A's condition number (rounding D itself, a small difference of large terms
  // on a stiff sheet, was not: a k = 1e7 sheet's steps gained energy). Newton's gradient and
  // its stopping test stay double.
  struct Single {
    std::vector<float> ux, uy, uz, alpha, beta;  // (slots)
    std::vector<float> rest_soa;                 // (6 B) R, entries as diag_soa's
    // (slots) 1 where a family's slot holds a spring: the mat-vec's mask (a slot without one
    // holds zeros, but 0 p is NaN where p is), in a byte where the layout's rest length is 8.
    std::vector<std::uint8_t> spring;
  } single;
  // What a refresh of the copies redoes: everything; R alone (only diag changed, as contact
  // terms change it); or the spring numbers alone (the assembly wrote R itself).
  enum class Refresh { All, Rest, Springs };
  // Fills `single` from the double numbers, where the matrix keeps one (ImplicitDef::
  // single_from): the floor that assembles A supplies it with the pattern (implicit/
  // sparse_system.h), as it does `multiply`; null where the mat-vec reads the double numbers.
  using SingleRefresh = void (*)(SpringBlockMatrix& A, Refresh what);
  SingleRefresh refresh_single_copy = nullptr;
  int num_bodies() const { return static_cast<int>(diag.size()); }
  std::size_t num_springs() const { return a.size(); }
  Vec3 u(std::size_t s) const {
    const std::size_t k = slot[s];
    return Vec3(ux[k], uy[k], uz[k]);
  }
  Mat3 off(std::size_t s) const { return block(alpha[slot[s]], beta[slot[s]], u(s)); }
  Mat3 off_projected(std::size_t s) const {
    return block(alpha_projected[slot[s]], beta_projected[slot[s]], u(s));
  }
  // Makes the matrix the projected one (the blocks the preconditioners use).
  void use_projected() {
    diag = diag_projected;
    alpha = alpha_projected;
    beta = beta_projected;
    refresh_copies();
  }
  // diag_soa from diag, and `single` where the matrix keeps one.
  void refresh_copies(Refresh what = Refresh::All) {
    to_soa(diag, diag_soa);
    if (refresh_single_copy) refresh_single_copy(*this, what);
  }
  static void to_soa(const std::vector<Mat3>& blocks, std::vector<double>& soa) {
    const std::size_t B = blocks.size();
    soa.resize(6 * B);
    for (std::size_t i = 0; i < B; ++i) {
      const Mat3& D = blocks[i];
      const double entry[6] = {D(0, 0), D(1, 1), D(2, 2), D(0, 1), D(0, 2), D(1, 2)};
      for (int e = 0; e < 6; ++e) soa[e * B + i] = entry[e];
    }
  }

 private:
  static Mat3 block(double alpha, double beta, const Vec3& u) {
    Mat3 G = alpha * (u * u.transpose());
    G.diagonal().array() += beta;
    return G;
  }
};

}  // namespace clothsim
