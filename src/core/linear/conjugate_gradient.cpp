#include "conjugate_gradient.h"

#include <algorithm>
#include <cmath>

#include "cg_kernels.h"

namespace clothsim {

namespace {


// z = the preconditioner applied to r, filtered; returns r . z. Block Jacobi runs as one SIMD
// pass that also takes r . z (before the filter: r is in the filter's range, so r . S z =
// S r . z = r . z, to rounding).
double precondition(const SpringBlockMatrix& A, const Preconditioner* pre,
                    const VelocityFilter* filter, const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) {
  double rz;
  if (pre) {
    pre->apply(r, z);
    if (filter) filter->apply(z);
    rz = matrix_dot(r, z);
  } else {
    const int B = A.num_bodies();
    z.resize(3, B);
    rz = simd_jacobi(A.diag_inverse_soa.data(), static_cast<std::size_t>(B), r.data(), z.data());
    if (filter) filter->apply(z);
  }
  return rz;
}

// The trust region of Steihaug-Toint CG: x.M.x, x.M.p and p.M.p of the current iterate and
// direction in the preconditioner's norm (z = M^-1 r), by the recurrences of Conn, Gould &
// Toint (2000, 7.5.1) from x = 0: no pass over the vectors.
class TrustRegion {
 public:
  TrustRegion(const CgSettings& settings, bool from_guess, double rz)
      : on_(settings.trust_region && !from_guess), bounded_(on_ && std::isfinite(settings.trust_radius)),
        radius2_(settings.trust_radius * settings.trust_radius) {
    if (on_) pp_ = rz;  // p = z: z.M.z = r.z
  }
  bool on() const { return on_; }
  bool bounded() const { return bounded_; }
  double norm() const { return std::sqrt(xx_); }
  // Whether x + alpha p would leave the region.
  bool leaves(double alpha) const { return bounded_ && xx_ + alpha * (2.0 * xp_ + alpha * pp_) > radius2_; }
  void moved(double alpha) { xx_ += alpha * (2.0 * xp_ + alpha * pp_); }
  // After p = z + beta p (the step before it alpha, r.z now rz).
  void new_direction(double alpha, double beta, double rz) {
    if (!on_) return;
    xp_ = beta * (xp_ + alpha * pp_);
    pp_ = rz + beta * beta * pp_;
  }
  // x + tau p on the boundary, tau >= 0 the positive root (x is inside: CG starts at 0 and
  // `leaves` stops it before it crosses); returns tau.
  double to_boundary(Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& p) {
    double tau = 0.0;
    if (pp_ > 0.0 && xx_ < radius2_) tau = (-xp_ + std::sqrt(xp_ * xp_ + pp_ * (radius2_ - xx_))) / pp_;
    if (tau > 0.0) x += tau * p;
    xx_ = radius2_;
    return tau;
  }

 private:
  const bool on_;       // measuring |x|
  const bool bounded_;  // and holding it within the radius
  double radius2_, xx_ = 0.0, xp_ = 0.0, pp_ = 0.0;
};

// q(x + t p) - q(x) for the model q(x) = 1/2 x.A x - b.x: -t p.r + t^2 p.A p / 2, where CG's
// p.r equals r.z (p = z + beta p_prev and p_prev.r = 0).
double model_change(double t, double rz, double pq) { return t * (0.5 * t * pq - rz); }

// CG's start: r = S (b - A x) from the caller's guess (a warm start, x filtered), else x = 0
// and r = S b. Returns q(x): -(x.b + x.r) / 2 from a guess (A x = b - r on the filter's
// range), 0 from zero.
double start(const SpringBlockMatrix& A, const Eigen::Matrix3Xd& b, Eigen::Matrix3Xd& x, bool from_guess,
             const VelocityFilter* filter, CgBuffers& buf) {
  if (from_guess) {
    if (filter) filter->apply(x);
    A.multiply(A, x, buf.q);
    buf.r = b - buf.q;
  } else {
    x.setZero(3, b.cols());
    buf.r = b;
  }
  if (filter) filter->apply(buf.r);
  return from_guess ? -0.5 * (matrix_dot(x, b) + matrix_dot(x, buf.r)) : 0.0;
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
  result.model_value = start(A, b, x, from_guess, filter, buf);
  double r_norm = buf.r.norm();
  result.relative_residual = r_norm / b_norm;
  if (r_norm <= stop) return result;  // the guess is already good enough
  double rz = precondition(A, pre, filter, buf.r, buf.z);
  buf.p = buf.z;
  TrustRegion region(settings, from_guess, rz);
  const std::size_t n = static_cast<std::size_t>(b.size());
  while (result.iterations < settings.max_iterations) {
    A.multiply(A, buf.p, buf.q);
    filtered(buf.q);
    const double pq = matrix_dot(buf.p, buf.q);
    if (!(pq > 0.0)) {  // A is not positive definite along p (or NaN): CG cannot go on
      result.converged = false;
      result.negative_curvature = true;
      // Along p the model falls without bound: to the boundary (r . p = rz > 0, so forward
      // descends). Without a region, on the first direction: take it rather than nothing.
      if (region.bounded() && std::isfinite(pq)) {
        result.model_value += model_change(region.to_boundary(x, buf.p), rz, pq);
        result.boundary = true;
      } else if (result.iterations == 0 && !from_guess && std::isfinite(pq)) {
        x = buf.p;
        result.model_value = model_change(1.0, rz, pq);
      }
      result.step_norm = region.norm();
      return result;
    }
    const double alpha = rz / pq;
    if (region.leaves(alpha)) {  // the model's minimiser along p lies outside: stop on the boundary
      result.model_value += model_change(region.to_boundary(x, buf.p), rz, pq);
      ++result.iterations;
      result.converged = false;
      result.boundary = true;
      result.step_norm = region.norm();
      return result;
    }
    if (region.on()) region.moved(alpha);
    result.model_value -= 0.5 * alpha * rz;  // model_change(alpha, rz, pq) with alpha pq = rz
    // x += alpha p, r -= alpha q and |r| in one pass (cg_kernels.h)
    r_norm = std::sqrt(simd_update_iterate(x.data(), buf.r.data(), buf.p.data(), buf.q.data(), alpha, n));
    ++result.iterations;
    result.relative_residual = r_norm / b_norm;
    if (r_norm <= stop) {
      result.step_norm = region.norm();
      return result;
    }
    const double rz_next = precondition(A, pre, filter, buf.r, buf.z);
    simd_xpby(buf.p.data(), buf.z.data(), rz_next / rz, n);  // p = z + beta p
    region.new_direction(alpha, rz_next / rz, rz_next);
    rz = rz_next;
  }
  result.converged = false;
  result.step_norm = region.norm();
  return result;
}

}  // namespace clothsim
