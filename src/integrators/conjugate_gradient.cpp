#include "integrators/conjugate_gradient.h"

#include <cmath>

namespace clothsim {

namespace {

double dot(const Eigen::Matrix3Xd& u, const Eigen::Matrix3Xd& w) {
  return u.cwiseProduct(w).sum();
}

void precondition(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) {
  const int B = A.num_bodies();
  z.resize(3, B);
  for (int i = 0; i < B; ++i) z.col(i).noalias() = A.diag_inverse[i] * r.col(i);
}

}  // namespace

CgResult solve_pcg(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, Eigen::Matrix3Xd& x,
                   int max_iterations, double tolerance, CgBuffers& buf) {
  CgResult result;
  x.setZero(3, b.cols());
  const double b_norm = b.norm();
  if (b_norm == 0.0) return result;  // x = 0 is exact

  buf.r = b;  // r = b - A 0
  precondition(A, buf.r, buf.z);
  buf.p = buf.z;
  double rz = dot(buf.r, buf.z);
  result.relative_residual = 1.0;
  while (result.iterations < max_iterations) {
    multiply(A, buf.p, buf.q);
    const double pq = dot(buf.p, buf.q);
    if (!(pq > 0.0)) {  // A is not positive definite along p (or NaN): CG cannot go on
      result.converged = false;
      return result;
    }
    const double alpha = rz / pq;
    x.noalias() += alpha * buf.p;
    buf.r.noalias() -= alpha * buf.q;
    ++result.iterations;
    result.relative_residual = buf.r.norm() / b_norm;
    if (result.relative_residual <= tolerance) return result;
    precondition(A, buf.r, buf.z);
    const double rz_next = dot(buf.r, buf.z);
    buf.p = buf.z + (rz_next / rz) * buf.p;
    rz = rz_next;
  }
  result.converged = false;
  return result;
}

}  // namespace clothsim
