#include "integrators/conjugate_gradient.h"

#include <algorithm>
#include <cmath>

namespace clothsim {

namespace {

double dot(const Eigen::Matrix3Xd& u, const Eigen::Matrix3Xd& w) {
  return u.cwiseProduct(w).sum();
}

void precondition(const SpringBlockMatrix& A, const CholeskyPreconditioner* factor,
                  const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) {
  if (factor) {
    factor->apply(r, z);
    return;
  }
  const int B = A.num_bodies();
  z.resize(3, B);
  for (int i = 0; i < B; ++i) z.col(i).noalias() = A.diag_inverse[i] * r.col(i);
}

}  // namespace

CgResult solve_pcg(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, Eigen::Matrix3Xd& x,
                   const CgSettings& settings, CgBuffers& buf, const VelocityFilter* filter,
                   const CholeskyPreconditioner* factor) {
  const auto filtered = [filter](Eigen::Matrix3Xd& v) {
    if (filter) filter->apply(v);
  };
  if (factor && !factor->ready()) factor = nullptr;
  CgResult result;
  const double b_norm = b.norm();
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
    multiply(A, x, buf.q);  // a warm start: r = b - A x from the caller's guess
    buf.r = b - buf.q;
  } else {
    x.setZero(3, b.cols());
    buf.r = b;
  }
  filtered(buf.r);
  double r_norm = buf.r.norm();
  result.relative_residual = r_norm / b_norm;
  if (r_norm <= stop) return result;  // the guess is already good enough
  precondition(A, factor, buf.r, buf.z);
  filtered(buf.z);
  buf.p = buf.z;
  double rz = dot(buf.r, buf.z);
  while (result.iterations < settings.max_iterations) {
    multiply(A, buf.p, buf.q);
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
    x.noalias() += alpha * buf.p;
    buf.r.noalias() -= alpha * buf.q;
    ++result.iterations;
    r_norm = buf.r.norm();
    result.relative_residual = r_norm / b_norm;
    if (r_norm <= stop) return result;
    precondition(A, factor, buf.r, buf.z);
    filtered(buf.z);
    const double rz_next = dot(buf.r, buf.z);
    buf.p = buf.z + (rz_next / rz) * buf.p;
    rz = rz_next;
  }
  result.converged = false;
  return result;
}

}  // namespace clothsim
