// A geometric multigrid V-cycle on the cloth's grid, as PCG's preconditioner (issue #37).
//
// Block-Jacobi PCG needs iterations in proportion to the grid's side on a refined sheet (its
// condition number grows as the Laplacian's, N^2: 18 -> 35 -> 67 CG iterations per Newton
// iteration from 32x32 to 128x128), and the sparse factor's cost grows as n^1.5. A V-cycle
// removes the smooth error on coarser grids, where it is rough again, so its contraction per
// cycle does not depend on the side (Briggs, Henson & McCormick, "A Multigrid Tutorial", 2000;
// Tamstorf, Jones & McCormick 2015 for cloth).
//
// The grid is regular, so the hierarchy is geometric: level l + 1 keeps the even rows and
// columns of level l (and the last, so the edges stay), and the prolongation P interpolates
// bilinearly, per body, the same weight on x, y and z. The coarse operators are Galerkin's,
// A_{l+1} = P^T A_l P in 3x3 blocks, so nothing about springs is assumed below the finest
// level. Bodies past the grid (spheres) are carried to the coarsest level as they are.
//
// The finest operator is the projected step Hessian with held contacts filtered as the sparse
// factor has them: S A S + (I - S) (cholesky_preconditioner.h), SPD. Immovable bodies
// (identity rows) are left out of P: the coarse grids never move them, and the smoothing
// leaves them at zero.
//
// The cycle is symmetric: on the finest level a Chebyshev polynomial in block-Jacobi-scaled A
// before and after the coarse correction (chebyshev_smoother.cpp: mat-vecs in the spring form,
// cheaper than Gauss-Seidel's block rows there), on the coarser ones forward block Gauss-Seidel before
// and backward after (the adjoint sweep), an exact dense Cholesky solve on the coarsest level.
// So M^-1 is symmetric positive definite and CG may use it (Tatebe 1993, "The multigrid
// preconditioned conjugate gradient method").
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "block_matrix.h"
#include "preconditioner.h"
#include "velocity_filter.h"

namespace clothsim {

// A symmetric matrix in 3x3 blocks, both triangles stored, by rows, each row's diagonal block
// first.
struct BlockRows {
  std::vector<int> start;         // (n + 1) row i's blocks: start[i] .. start[i + 1]
  std::vector<int> col;           // (blocks) column of each block
  std::vector<Mat3> value;        // (blocks)
  std::vector<Mat3> diag_inverse; // (n) the diagonal blocks' inverses (the smoother's)
  int size() const { return static_cast<int>(start.size()) - 1; }
  void multiply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& y) const;  // y = A x
};

// The prolongation from one level to the next coarser: fine body i = sum_k weight_k coarse_k,
// k in start[i] .. start[i + 1], and the same weights by coarse body (its transpose).
struct GridTransfer {
  std::vector<int> start, coarse;      // (fine + 1), (entries)
  std::vector<double> weight;          // (entries)
  std::vector<int> t_start, t_fine;    // (coarse + 1), (entries)
  std::vector<double> t_weight;        // (entries)
  int fine_bodies = 0, coarse_bodies = 0;
  int coarse_nx = 0, coarse_ny = 0;    // the coarse grid
};

// The bilinear prolongation of an nx x ny grid of particles (particle p = j nx + i) followed
// by `others` bodies carried as they are; an axis of more than 2 particles is halved.
GridTransfer grid_transfer(int nx, int ny, int others);

// The finest level's smoother. Chebyshev (chebyshev_smoother.cpp) contracts as much per cycle
// as the symmetric Gauss-Seidel sweep, through the spring form's SIMD mat-vec rather than 3x3
// block rows (a PCG iteration 0.58x the CPU at 128 x 128, BENCHMARKS.md #37); coarser levels
// (Galerkin blocks, no spring form) keep Gauss-Seidel.
enum class FineSmoother { GaussSeidel, Chebyshev };
struct MultigridOptions {
  FineSmoother fine = FineSmoother::Chebyshev;
  int degree = 2;       // Chebyshev's polynomial degree: degree - 1 mat-vecs before, degree after
  double lower = 0.3;   // its interval: [lower, 1] times D^-1 A's largest eigenvalue (estimated)
};

class MultigridPreconditioner : public Preconditioner {
 public:
  void set_options(const MultigridOptions& o) { options_ = o; }
  // The levels' transfers for B bodies, the first nx ny of them a grid: once per model.
  // Coarsens until at most kCoarsest bodies remain (or no axis can be halved).
  void analyse(const SpringBlockMatrix& A, int grid_nx, int grid_ny);
  bool analysed() const { return analysed_; }
  // The operators from A's projected blocks, held contacts filtered, immovable bodies
  // (inv_mass 0, (B)) left out of P. False where a level is not SPD (a non-finite matrix).
  bool build(const SpringBlockMatrix& A, const VelocityFilter& filter, const Eigen::VectorXd& inv_mass);
  bool ready() const override { return ready_; }
  void invalidate() { ready_ = false; }
  // z = S M^-1 r: one V-cycle from zero, filtered.
  void apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const override;

  int levels() const { return static_cast<int>(op_.size()); }
  // The top of the finest Chebyshev interval: D^-1 A's largest eigenvalue, estimated, raised.
  double smoother_lambda_max() const { return lambda_max_; }
  const BlockRows& level(int l) const { return op_[l]; }
  // What a cycle costs, in block-Jacobi PCG iterations: its blocks visited (two sweeps and a
  // residual on each level, the coarsest's dense solve) against the finest mat-vec's.
  double cycle_cost() const { return cycle_cost_; }
  double build_cost() const { return build_cost_; }  // likewise, the Galerkin products

  static constexpr int kCoarsest = 100;  // bodies at most on the coarsest level (dense solve)

 private:
  void load_finest(const SpringBlockMatrix& A, const VelocityFilter& filter);
  void galerkin(int l, bool symbolic);  // op_[l + 1] = P^T op_[l] P: its pattern, or its values
  bool invert_diagonals(BlockRows& M);
  void cycle(int l) const;
  void coarse_correct(int l) const;
  // The finest level in spring form (chebyshev_smoother.cpp): y = S A S y, its largest
  // eigenvalue under block Jacobi, and the smoothing x += p(D^-1 A) D^-1 (b - A x).
  void load_spring_form(const SpringBlockMatrix& A);
  void fine_multiply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& y) const;
  void estimate_lambda_max();
  void chebyshev(Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& b, bool from_zero) const;

  std::vector<GridTransfer> transfer_;  // level l -> l + 1
  std::vector<BlockRows> op_;           // level operators, finest first
  std::vector<int> spring_ab_, spring_ba_;  // (S) where spring s's two blocks sit in op_[0]
  std::vector<std::uint8_t> fixed_;     // (B) immovable bodies, out of P
  VelocityFilter held_;                 // the filter at the last build
  std::vector<int> marker_;             // scratch of galerkin
  std::vector<std::vector<int>> route_; // per level: the coarse entry each product adds into
  Eigen::LLT<Eigen::MatrixXd> coarsest_{Eigen::MatrixXd()};  // (factored empty: no member left unset)
  mutable std::vector<Eigen::Matrix3Xd> x_, b_, t_;  // per level: iterate, right side, scratch
  MultigridOptions options_;
  SpringBlockMatrix fine_;              // the projected finest matrix in spring form (Chebyshev)
  std::vector<double> fine_inverse_soa_;  // (6 B) op_[0]'s diagonal inverses, as simd_jacobi reads
  double lambda_max_ = 0.0;             // of D^-1 A on the finest level
  Eigen::Matrix3Xd power_;              // the power iteration's vector, kept between builds
  mutable Eigen::Matrix3Xd cheb_r_, cheb_d_, cheb_q_;  // (3 x B) Chebyshev's scratch
  double cycle_cost_ = 0.0, build_cost_ = 0.0;
  bool analysed_ = false, ready_ = false;
};

}  // namespace clothsim
