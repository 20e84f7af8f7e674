// The V-cycle's finest-level smoother as a Chebyshev polynomial in block-Jacobi-scaled A
// (Adams, Brezina, Hu & Tuminaro 2003, "Parallel multigrid smoothing: polynomial versus
// Gauss-Seidel"). Gauss-Seidel reads every 3x3 block by rows, two triangles of 72 bytes per
// spring; a polynomial smoother needs only mat-vecs, which the spring form (5 numbers per
// spring, SIMD over the layout's families) does at a fraction of that: the finest level is
// where the cycle spends most of its time (BENCHMARKS.md #37).
//
// The same polynomial before and after the coarse correction keeps the cycle symmetric, and
// positive definite while the interval's top bounds D^-1 A's spectrum (the estimate below is
// raised by 10 %, the spectrum's top is what the smoother must not amplify).
#include <cmath>
#include <cstdint>

#include "cg_kernels.h"
#include "multigrid_preconditioner.h"

namespace clothsim {

namespace {

constexpr int kPowerIterations = 15;      // at the first build, from a rough start
constexpr int kWarmPowerIterations = 5;   // at later ones, from the last build's vector
constexpr double kLambdaMargin = 1.1;

}  // namespace

// The finest matrix's projected blocks as A's own spring form: the same pattern, the
// projected numbers (SPD whatever A is), and op_[0]'s filtered diagonal inverses.
void MultigridPreconditioner::load_spring_form(const SpringBlockMatrix& A) {
  if (fine_.slot.size() != A.slot.size()) {  // the pattern, once per model
    fine_.multiply = A.multiply;
    fine_.refresh_single_copy = A.refresh_single_copy;
    fine_.a = A.a;
    fine_.b = A.b;
    fine_.slot = A.slot;
    fine_.layout = A.layout;
  }
  fine_.ux = A.ux;
  fine_.uy = A.uy;
  fine_.uz = A.uz;
  fine_.alpha = A.alpha_projected;
  fine_.beta = A.beta_projected;
  fine_.diag = A.diag_projected;
  fine_.refresh_copies();
  SpringBlockMatrix::to_soa(op_[0].diag_inverse, fine_inverse_soa_);
}

// y = S A S x + (I - S) x for x in the range of S: A x, filtered (held normals).
void MultigridPreconditioner::fine_multiply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& y) const {
  fine_.multiply(fine_, x, y);
  held_.apply(y);
}

// D^-1 A's largest eigenvalue by the power iteration.
void MultigridPreconditioner::estimate_lambda_max() {
  const int B = fine_.num_bodies();
  const std::size_t n = static_cast<std::size_t>(B);
  int iterations = kWarmPowerIterations;
  if (power_.cols() != B || !power_.allFinite() || power_.norm() == 0.0) {
    // A rough start (every frequency present), the same at every run: hashed values in +-1.5.
    power_.resize(3, B);
    for (Eigen::Index k = 0; k < power_.size(); ++k)
      power_.data()[k] = ((static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ull) >> 62) - 1.5;
    iterations = kPowerIterations;
  }
  held_.apply(power_);
  Eigen::Matrix3Xd Av(3, B), z(3, B);
  double lambda = 0.0;
  for (int k = 0; k < iterations; ++k) {
    power_ /= power_.norm();
    fine_multiply(power_, Av);
    simd_jacobi(fine_inverse_soa_.data(), n, Av.data(), z.data());
    lambda = z.norm();  // |D^-1 A v| with |v| = 1: tends to the top eigenvalue
    power_.swap(z);
  }
  lambda_max_ = kLambdaMargin * lambda;
}

// x += p(D^-1 A) D^-1 (b - A x), p of the given degree, on [lower, 1] lambda_max (Saad,
// "Iterative Methods for Sparse Linear Systems", Algorithm 12.1). From zero: r = b, one
// mat-vec fewer.
void MultigridPreconditioner::chebyshev(Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& b, bool from_zero) const {
  const int B = fine_.num_bodies();
  const std::size_t n = static_cast<std::size_t>(B);
  const double top = lambda_max_, bottom = options_.lower * lambda_max_;
  const double theta = 0.5 * (top + bottom), delta = 0.5 * (top - bottom), sigma = theta / delta;
  if (from_zero) {
    cheb_r_ = b;
  } else {
    fine_multiply(x, cheb_q_);
    cheb_r_ = b - cheb_q_;
  }
  cheb_d_.resize(3, B);
  simd_jacobi(fine_inverse_soa_.data(), n, cheb_r_.data(), cheb_d_.data());
  cheb_d_ /= theta;
  double rho_old = 1.0 / sigma;
  for (int k = 1;; ++k) {
    x += cheb_d_;
    if (k == options_.degree) break;
    fine_multiply(cheb_d_, cheb_q_);
    cheb_r_ -= cheb_q_;
    const double rho = 1.0 / (2.0 * sigma - rho_old);
    cheb_q_.resize(3, B);
    simd_jacobi(fine_inverse_soa_.data(), n, cheb_r_.data(), cheb_q_.data());  // D^-1 r
    cheb_d_ = (rho * rho_old) * cheb_d_ + (2.0 * rho / delta) * cheb_q_;
    rho_old = rho;
  }
}

}  // namespace clothsim
