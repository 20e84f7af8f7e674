#include "conjugate_gradient.h"

#include <algorithm>
#include <cmath>

#include "cg_kernels.h"

namespace clothsim {

namespace {

double dot(const Eigen::Matrix3Xd& u, const Eigen::Matrix3Xd& w) {
  return simd_dot(u.data(), w.data(), static_cast<std::size_t>(u.size()));
}

// z = the preconditioner applied to r, filtered; returns r . z. Block Jacobi runs as one SIMD
// pass that also takes r . z (before the filter: r is in the filter's range, so r . S z =
// S r . z = r . z, to rounding).
double precondition(const SpringBlockMatrix& A, const Preconditioner* pre,
                    const VelocityFilter* filter, const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) {
  double rz;
  if (pre) {
    pre->apply(r, z);
    if (filter) filter->apply(z);
    rz = dot(r, z);
  } else {
    const int B = A.num_bodies();
    z.resize(3, B);
    rz = simd_jacobi(A.diag_inverse_soa.data(), static_cast<std::size_t>(B), r.data(), z.data());
    if (filter) filter->apply(z);
  }
  return rz;
}

}  // namespace

CgResult solve_pcg(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, Eigen::Matrix3Xd& x,
                   const CgSettings& settings, CgBuffers& buf, const VelocityFilter* filter,
                   const Preconditioner* pre) {
  const auto filtered = [filter](Eigen::Matrix3Xd& v) {
    if (filter) filter->apply(v);
  };
  if (pre && !pre->ready()) pre = nullptr;
  CgResult result;
  const double b_norm = settings.b_norm >= 0.0 ? settings.b_norm : b.norm();
  if (b_norm == 0.0) {  // x = 0 is exact
    x.setZero(3, b.cols());
    return result;
  }
  // Stop at whichever is looser: the relative tolerance, or the absolute accuracy the caller
  // actually needs (a Newton step needs its linear solve no more accurate than its own test).
  const double stop = std::max(settings.tolerance * b_norm, settings.absolute_tolerance);
  const bool from_guess = settings.from_guess && x.cols() == b.cols() && x.allFinite();
  if (from_guess) {
    filtered(x);
    A.multiply(A, x, buf.q);  // a warm start: r = b - A x from the caller's guess
    buf.r = b - buf.q;
  } else {
    x.setZero(3, b.cols());
    buf.r = b;
  }
  filtered(buf.r);
  double r_norm = buf.r.norm();
  result.relative_residual = r_norm / b_norm;
  if (r_norm <= stop) return result;  // the guess is already good enough
  double rz = precondition(A, pre, filter, buf.r, buf.z);
  buf.p = buf.z;
  const std::size_t n = static_cast<std::size_t>(b.size());
  while (result.iterations < settings.max_iterations) {
    A.multiply(A, buf.p, buf.q);
    filtered(buf.q);
    const double pq = dot(buf.p, buf.q);
    if (!(pq > 0.0)) {  // A is not positive definite along p (or NaN): CG cannot go on
      result.converged = false;
      result.negative_curvature = true;
      // On the first direction: take it (b . p > 0: it descends), rather than nothing.
      if (result.iterations == 0 && !from_guess && std::isfinite(pq)) x = buf.p;
      return result;
    }
    const double alpha = rz / pq;
    // x += alpha p, r -= alpha q and |r| in one pass (cg_kernels.h)
    r_norm = std::sqrt(simd_update_iterate(x.data(), buf.r.data(), buf.p.data(), buf.q.data(), alpha, n));
    ++result.iterations;
    result.relative_residual = r_norm / b_norm;
    if (r_norm <= stop) return result;
    const double rz_next = precondition(A, pre, filter, buf.r, buf.z);
    simd_xpby(buf.p.data(), buf.z.data(), rz_next / rz, n);  // p = z + beta p
    rz = rz_next;
  }
  result.converged = false;
  return result;
}

}  // namespace clothsim
