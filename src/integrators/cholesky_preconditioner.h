// A sparse Cholesky factor of the projected step Hessian, as PCG's preconditioner.
//
// Block Jacobi (conjugate_gradient.h) is exact where mass dominates the step's matrix, at the
// small steps the explicit methods need. At one step per frame on stiff cloth it is not:
// H = M + h^2 K has condition number about h^2 k / m times the grid's Laplacian spread
// (stiff.yaml at 1/60 s: 555 x ~100), and PCG needed 400-700 iterations a step there, most of
// the step's cost, with inexact directions that stalled Newton at impacts. A cloth's matrix is
// a 2D grid's, whose Cholesky factor under a fill-reducing (AMD) ordering has O(n log n)
// entries: factoring it costs a few mat-vecs' worth at 25 x 25 and solving with it one or two,
// and PCG preconditioned by the factor of the matrix it solves converges in one iteration.
//
// So implicit_euler factors the projected Hessian P (sparse_system.h: SPD at any step) when
// block-Jacobi PCG turns out slow, and keeps using the factor while it stays good: PCG on the
// exact Hessian, preconditioned by P^-1 of an earlier iterate, needs a few iterations where
// the two are close, and more as they drift; the iteration count is what decides when to
// factor again (implicit_euler.cpp), never an assumption. Any SPD P gives a correct solve;
// only the iteration count depends on how good it is.
//
// Held contacts (velocity_filter.h) enter the factored matrix as Baraff & Witkin's filter
// does in PCG: S P S + (I - S), which is SPD, equal to P on the free directions and the
// identity along held normals (Ascher & Boxerman 2003, "On the modified conjugate gradient
// method in cloth simulation").
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <vector>

#include "integrators/sparse_system.h"
#include "integrators/velocity_filter.h"

namespace clothsim {

class CholeskyPreconditioner {
 public:
  // Builds the (3B x 3B) pattern of A's blocks and its fill-reducing symbolic factorisation:
  // once per model (the only allocating call but factorize's first).
  void analyse(const SpringBlockMatrix& A);
  bool analysed() const { return analysed_; }
  void reset() { analysed_ = ready_ = false; }  // a new model: analyse again

  // Factors S P S + (I - S), P the projected blocks of A (the last assembly). Returns false if
  // the factorisation failed (not SPD: a non-finite matrix); the factor is then unusable.
  bool factorize(const SpringBlockMatrix& A, const VelocityFilter& filter);
  bool ready() const { return ready_; }
  void invalidate() { ready_ = false; }

  // z = (S P S + (I - S))^-1 r, r and z (3 x B).
  void apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const;

  // What a factorisation costs, in block-Jacobi PCG iterations (one block mat-vec and one
  // block-diagonal solve each), estimated from the symbolic factorisation: sum_j c_j^2
  // multiply-adds for column counts c_j of L, against 9 (B + 2 S) + 9 B for the iteration.
  // Eigen's simplicial LLT runs slower per multiply-add than the hand-written mat-vec; the
  // ratio, measured, is folded in (cholesky_preconditioner.cpp). A solve with the factor
  // costs about 4 nnz(L).
  double factor_cost() const { return factor_cost_; }
  double solve_cost() const { return solve_cost_; }

 private:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  Matrix K_;  // lower triangle of the factored matrix
  // For each body, the value index of its diagonal block's entry (r, c), r >= c, at 3 r + c;
  // for each spring, its block's 9 entries (lower triangle of the whole matrix) at 3 r + c.
  std::vector<int> diag_index_;  // (9 B), -1 above the diagonal
  std::vector<int> off_index_;   // (9 S)
  std::vector<bool> off_transposed_;  // (S) the spring's block stored as (b, a): a < b
  // Eigen's simplicial LLT, with its symbolic factor (L's column pointers) readable.
  struct Llt : Eigen::SimplicialLLT<Matrix, Eigen::Lower, Eigen::AMDOrdering<int>> {
    const int* column_pointers() const { return this->m_matrix.outerIndexPtr(); }
  };
  Llt llt_;
  double factor_cost_ = 0.0, solve_cost_ = 0.0;
  std::vector<Mat3> filter_;  // (B) S_i (identity for free bodies), scratch for factorize
  bool analysed_ = false, ready_ = false;
};

}  // namespace clothsim
