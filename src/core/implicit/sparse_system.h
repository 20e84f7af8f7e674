// The linear system of one Newton iteration of backward Euler, in a fixed block pattern.
//
// implicit_euler solves backward Euler as the minimisation of the step potential Phi(dv)
// (step_potential.h); its Newton systems are H d = -g with the Hessian
//     H = M + h c I + h^2 sum_s K_s,
// K_s the spring's step block of spring_force.h (stiffness ks + kd/h along the spring, its
// tension / l across it). A spring (a, b) touches four 3x3 blocks: (a,a), (b,b) get -G and
// (a,b), (b,a) get +G, with G = -h^2 K_s. So the pattern is known once the springs are: one
// block per body on the diagonal and one per spring off it. It is stored that way, block by
// spring, built once per model and refilled in place every iteration: no index search, no
// allocation in the step.
//
// Every K_s is symmetric. Across a compressed spring its transverse term is negative, and at
// a large step it can make H indefinite. So the matrix comes in two kinds:
//  - exact (project = false): Phi's true Hessian, with which Newton converges quadratically;
//    where CG on it meets negative curvature, the solver truncates there (implicit_euler.cpp);
//  - projected (project = true): every K_s's transverse term clamped at 0 (Martin et al.
//    2011's per-element projection), so H is SPD at any step size, CG cannot break down and
//    its solution always descends; Baraff & Witkin's single step.
// The preconditioners are built from the projected blocks in both cases, so they are SPD
// whatever the matrix.
//
// Immovable bodies (inverse mass 0: pinned particles, kinematic spheres) are filtered by
// removing their rows and columns: their diagonal block is the identity, every block that
// couples them is zero, and their right-hand side is zero, so the solve leaves dv = 0 there
// (the effect of Baraff & Witkin's filter S for fully constrained particles).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/model.h"
#include "core/springs/spring_force.h"

namespace clothsim {

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
  // writes diag otherwise calls refresh_diagonal_soa().
  std::vector<double> diag_soa;          // (6 B)
  std::vector<double> diag_inverse_soa;  // (6 B)
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
    refresh_diagonal_soa();
  }
  // diag_soa from diag.
  void refresh_diagonal_soa() { to_soa(diag, diag_soa); }
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

// Sizes the pattern for a model's bodies and springs (the only allocating call).
void build_pattern(const Model& model, SpringBlockMatrix& A);

// Refills A = H at the end-of-step positions y (3 x B), with start_length the springs'
// lengths at the start of the step by slot (step_lengths, step_potential.h), exact or
// projected (above): the layout's families in SIMD (potential_kernels.h), their blocks'
// contributions to the diagonal summed per particle as the walk goes, then the others. With
// `block_jacobi`, also the block-Jacobi preconditioner (diag_inverse); without, it is left
// stale, for a solver that preconditions with the sparse factor and inverts the diagonal only
// when it needs to (invert_diagonal: a 3x3 inverse per body).
void assemble_step_hessian(const Model& model, const Eigen::VectorXd& inv_mass, double h,
                           const std::vector<double>& start_length, const Eigen::Matrix3Xd& y,
                           bool project, SpringBlockMatrix& A, bool block_jacobi = true);

// The scalar reference: every spring in spring order, each block through step_spring_block
// (spring_force.h), the projected diagonal as the exact one corrected for the compressed
// springs. The same matrix to rounding: the diagonal blocks' sums run in another order, and
// the SIMD blocks' u and T / l are products with 1 / l rather than quotients (an ulp or two).
// (Where neither end of a spring moves it leaves the slot's u as it was; the SIMD pass writes
// it. Either way the block is zero.)
void assemble_step_hessian_scalar(const Model& model, const Eigen::VectorXd& inv_mass, double h,
                                  const std::vector<double>& start_length,
                                  const Eigen::Matrix3Xd& y, bool project, SpringBlockMatrix& A,
                                  bool block_jacobi = true);

// A.diag_inverse = A.diag_projected^-1, blockwise.
void invert_diagonal(SpringBlockMatrix& A);

// y = A p (3 x B): the diagonal blocks, then the layout's families in SIMD, then the others.
void multiply(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y);

// The scalar reference: the diagonal, then every spring in spring order. The same product to
// rounding (the order of each entry's sum differs).
void multiply_scalar(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y);

}  // namespace clothsim
