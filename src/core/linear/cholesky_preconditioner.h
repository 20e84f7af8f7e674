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
//
// The factor is computed in 3x3 blocks, a body's three coordinates together (Davis 2005's
// up-looking LDL^T with block entries, bodies in AMD order), since every entry of the matrix
// belongs to one such block: Eigen's scalar simplicial LLT on the same matrix, indexing every
// scalar entry, took 2.8 times as long to factor and 1.8 times as long to solve (BENCHMARKS.md).
// The blocks' products run in SIMD (block_factor_kernels.h), a block column per vector.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "block_factor_kernels.h"
#include "block_matrix.h"
#include "preconditioner.h"
#include "velocity_filter.h"

namespace clothsim {

class CholeskyPreconditioner : public Preconditioner {
 public:
  // Orders A's bodies to reduce fill (AMD on the graph of springs) and computes the factor's
  // pattern (its elimination tree and column counts): once per model. L itself and the
  // factorisation's scratch are allocated by the first factorize. When even a factor without
  // fill (one block per pair of A) would take more than `budget_bytes`, it stops after
  // counting the pairs: factor_bytes() is then that least size, the costs infinite, and the
  // factor must not be built.
  void analyse(const SpringBlockMatrix& A, std::size_t budget_bytes = std::numeric_limits<std::size_t>::max());
  bool analysed() const { return analysed_; }
  void reset() { analysed_ = ready_ = false; }  // a new model: analyse again

  // Factors S P S + (I - S) = L D L^T, P the projected blocks of A (the last assembly).
  // Returns false if the factorisation failed (a pivot block not SPD: a non-finite matrix);
  // the factor is then unusable.
  bool factorize(const SpringBlockMatrix& A, const VelocityFilter& filter);
  bool ready() const override { return ready_; }
  void invalidate() { ready_ = false; }

  // z = (S P S + (I - S))^-1 r, r and z (3 x B).
  void apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const override;

  // What a factorisation and a solve cost, in block-Jacobi PCG iterations (one block mat-vec
  // and one block-diagonal solve each), from the factor's pattern: a 3x3 block product is 27
  // multiply-adds, against 9 (2 B + 2 S) for the iteration. The ratio of speeds per
  // multiply-add were measured to be about equal (cholesky_preconditioner.cpp).
  double factor_cost() const { return factor_cost_; }
  double solve_cost() const { return solve_cost_; }
  // What factorize() allocates for L and D (known after analyse).
  std::size_t factor_bytes() const {
    return factor_blocks() * (sizeof(Mat3) + sizeof(int)) + bodies_ * sizeof(Mat3) +
           2 * kBlockSlack * sizeof(double);
  }
  // Off-diagonal blocks of L; only a lower bound (A's pairs) when analyse stopped short.
  std::size_t factor_blocks() const { return blocks_; }

 private:
  void build_upper_pattern(const SpringBlockMatrix& A);       // analyse: A's blocks by column
  std::vector<int> count_columns(int B);                      // analyse: elimination tree, counts
  void estimate_costs(const std::vector<int>& count, std::size_t S, bool single);  // single: A.single
  void allocate_scratch(int B);                                // factorize: first time only
  void load_filtered(const SpringBlockMatrix& A, const VelocityFilter& filter);
  bool factor_rows(int B);
  int scatter_column(int k, int B);

  // Bodies are factored in a fill-reducing order: new index k is body order_[k], body i is
  // new index rank_[i]. The matrix's strictly upper blocks (i < k, new indices) by column k:
  // upper_start_[k] .. upper_start_[k + 1] in upper_row_, filled from the springs listed in
  // upper_spring_ (each spring's block added at one slot, transposed where flagged).
  std::vector<int> order_, rank_;
  std::vector<int> upper_start_, upper_row_;
  std::vector<int> spring_slot_;           // (S) the slot its block adds into
  std::vector<bool> spring_transposed_;    // (S) whether it adds as its transpose
  std::vector<Mat3> upper_;                // (slots) values, scratch for factorize
  std::vector<Mat3> diag_;                 // (B) diagonal blocks, new order, scratch

  // L D L^T, L unit lower triangular in 3x3 blocks stored by column: column j's blocks
  // L(row_[p], j) = value_[p] for p in column_start_[j] .. column_start_[j + 1], rows
  // increasing; D's blocks kept inverted.
  std::vector<int> parent_;                // (B) elimination tree
  // Blocks as block_factor_kernels.h stores them: L's and D^-1's compact (9 doubles, column
  // major, and kBlockSlack past the last), the row's scratch padded (12).
  std::vector<int> column_start_, row_;
  std::vector<double> value_, d_inverse_;

  // Scratch of the up-looking factorisation (one row of L at a time).
  std::vector<double> y_;                  // (12 x B)
  std::vector<int> flag_, pattern_, filled_;
  mutable std::vector<double> w_;          // (4 x B) scratch of apply

  std::size_t bodies_ = 0, blocks_ = 0;  // factor_bytes()' inputs, set by analyse
  double factor_cost_ = 0.0, solve_cost_ = 0.0;
  std::vector<Mat3> filter_;  // (B) S_i (identity for free bodies), scratch for factorize
  std::vector<std::uint8_t> filtered_;  // (B) 1 where S_i is not the identity, scratch
  bool analysed_ = false, ready_ = false;
};

}  // namespace clothsim
