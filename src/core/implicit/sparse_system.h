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

#include "step_form.h"
#include "core/model/model.h"
#include "core/linear/block_matrix.h"
#include "core/springs/spring_force.h"

namespace clothsim {

// Which matrix an assembly writes (above): Phi's true Hessian, or every compressed spring's
// transverse term clamped at 0 (SPD at any step: Baraff & Witkin's single step).
enum class HessianBlocks { Exact, Projected };
// Whether an assembly also forms the block-Jacobi inverse (diag_inverse), or leaves it stale
// for a solver that preconditions with the sparse factor (invert_diagonal when needed).
enum class JacobiInverse { Form, Skip };

// Sizes the pattern for a model's bodies and springs (the only allocating call). From
// `single_from` particles on (a run's ImplicitDef::single_from) the mat-vec reads a float copy;
// without it, as the model's own settings say.
void build_pattern(const Model& model, int single_from, SpringBlockMatrix& A);
void build_pattern(const Model& model, SpringBlockMatrix& A);

// Refills A = H at the end-of-step positions y (3 x B) for the step of form `form` (step_form.h),
// with start_length the dampers' reference lengths by slot (step_lengths' l_n for backward
// Euler, step_potential.h), exact or
// projected (above): the layout's families in SIMD (potential_kernels.h), their blocks'
// contributions to the diagonal summed per particle as the walk goes, then the others.
void assemble_step_hessian(const Model& model, const Eigen::VectorXd& inv_mass, const StepForm& form,
                           const std::vector<double>& start_length, const Eigen::Matrix3Xd& y,
                           HessianBlocks blocks, SpringBlockMatrix& A,
                           JacobiInverse jacobi = JacobiInverse::Form);

// The scalar reference: every spring in spring order, each block through step_spring_block
// (spring_force.h), the projected diagonal as the exact one corrected for the compressed
// springs. The same matrix to rounding: the diagonal blocks' sums run in another order, and
// the SIMD blocks' u and T / l are products with 1 / l rather than quotients (an ulp or two).
// (Where neither end of a spring moves it leaves the slot's u as it was; the SIMD pass writes
// it. Either way the block is zero.)
void assemble_step_hessian_scalar(const Model& model, const Eigen::VectorXd& inv_mass, const StepForm& form,
                                  const std::vector<double>& start_length,
                                  const Eigen::Matrix3Xd& y, HessianBlocks blocks,
                                  SpringBlockMatrix& A, JacobiInverse jacobi = JacobiInverse::Form);

// A.diag_inverse = A.diag_projected^-1, blockwise.
void invert_diagonal(SpringBlockMatrix& A);

// A.single from A's double numbers (block_matrix.h: the mat-vec's float copy); the pattern's
// refresh_single_copy where the matrix has a layout.
void refresh_single(SpringBlockMatrix& A, SpringBlockMatrix::Refresh what);

// y = A p (3 x B): the layout's families in SIMD, on A.single where the matrix keeps one (R p
// and each spring's block on the difference of its ends' p, block_matrix.h), else on the
// double numbers (D p and each spring's block on the other end's p); then the bodies no spring
// reaches, then the others. Without a layout, multiply_scalar.
void multiply(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y);

// The scalar reference in double: the diagonal, then every spring in spring order. multiply's
// product to rounding (the order of each entry's sum differs), or, from the float copy, to its
// numbers' rounding (within 1e-6 of |A| |p| per entry, and of p.A.p in energy on the
// projected matrix: tests/core/implicit/potential_kernels_test.cpp).
void multiply_scalar(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y);

}  // namespace clothsim
