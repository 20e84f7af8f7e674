// The linear system of one Newton iteration of backward Euler, in a fixed block pattern.
//
// Backward Euler on the velocity change dv (Baraff & Witkin 1998, "Large Steps in Cloth
// Simulation", eq. 15-16) linearises f(x + h (v + dv), v + dv) and solves
//     A dv = rhs,   A = M - h df/dv - h^2 df/dx.
// A spring (a, b) touches four 3x3 blocks of A: (a,a), (b,b) get -G and (a,b), (b,a) get +G,
// with G = h df_a/dv_a + h^2 df_a/dx_a (the Jacobians of spring_force.h; df_a/dx_b = -df_a/dx_a).
// So the pattern is known once the springs are: one block per body on the diagonal and one
// per spring off it. It is stored that way, block by spring, built once per model and
// refilled in place every iteration: no index search, no allocation in the step.
//
// Conjugate gradient needs A symmetric, and positive definite to be safe:
//  - The damper's position term of df/dx is not symmetric; it is always dropped (Baraff &
//    Witkin do the same). Newton then runs with an approximate Jacobian (an inexact
//    Newton), which still converges, linearly; the caller tests the true nonlinear residual.
//  - A compressed spring (l < l0) has a transverse stiffness -ks (1 - l0/l)(I - P) of the
//    wrong sign: it adds -h^2 ks (l0/l - 1) to A across the spring and, at large steps, can
//    make A indefinite and CG break down. With clamp_compression, (1 - l0/l) is clamped at
//    0 under compression, as many cloth codes do: such a spring keeps only its axial
//    stiffness -ks u u^T. Then every G is negative semi-definite
//    (-ks P - ks max(0, 1 - l0/l)(I - P) - kd P / h, times h^2), so A = M - sum G is SPD at
//    any step size. The price is a Jacobian that is wrong for compressed springs, and so
//    more Newton iterations; the caller therefore tries the exact stiffness first and
//    clamps only when CG fails on it (implicit_euler.cpp).
// Viscous air drag adds h c I to each cloth particle's diagonal block.
//
// Immovable bodies (inverse mass 0: pinned particles, kinematic spheres) are filtered by
// removing their rows and columns: their diagonal block is the identity, every block that
// couples them is zero, and their right-hand side is zero, so the solve leaves dv = 0 there
// (the effect of Baraff & Witkin's filter S for fully constrained particles).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "model.h"
#include "spring_force.h"

namespace clothsim {

struct SpringBlockMatrix {
  std::vector<std::int32_t> a, b;  // (S) block (a_s, b_s): the springs' index pairs
  std::vector<Mat3> diag;          // (B) diagonal blocks
  std::vector<Mat3> diag_inverse;  // (B) their inverses: the block-Jacobi preconditioner
  std::vector<Mat3> off;           // (S) block at (a_s, b_s); symmetric, so also at (b_s, a_s)
  int num_bodies() const { return static_cast<int>(diag.size()); }
};

// Sizes the pattern for a model's bodies and springs (the only allocating call).
void build_pattern(const Model& model, SpringBlockMatrix& A);

// Refills A = M - h df/dv - h^2 K at (x, v), K the symmetric stiffness part of df/dx
// (compression clamped if asked), immovable bodies filtered, and computes Jv = (df/dx) v
// (3 x B) with the EXACT df/dx (unclamped stiffness and the damper's position term): the
// term Baraff & Witkin's first right-hand side h (f + h (df/dx) v) needs (zero rows for
// immovable bodies). Only the matrix is approximated; the known part of the step, the
// positions moving by h v, is linearised exactly. With strong dampers (the drape's
// kd = 750 N s/m on 1 kg particles) the damper's term is most of it: leaving it out of
// the right-hand side as well cost a second Newton iteration on every step.
void assemble_backward_euler_matrix(const Model& model, const Eigen::Matrix3Xd& x,
                                    const Eigen::Matrix3Xd& v, const Eigen::VectorXd& inv_mass,
                                    double h, bool clamp_compression, SpringBlockMatrix& A,
                                    Eigen::Matrix3Xd& Jv);

// y = A p (3 x B).
void multiply(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& y);

}  // namespace clothsim
