// The spring-damper kernel and its Jacobians: pure functions of values, tested alone.
//
// Force on particle a from the spring (a, b), exactly the seed report's formula, with
// d = x_a - x_b, l = |d|, u = d / l:
//     f_a = -ks (l - l0) u  -  kd ((v_a - v_b) . u) u,        f_b = -f_a.
// The damper acts along the spring only, so it damps stretching, not rigid rotation.
//
// Jacobians (Baraff & Witkin 1998, "Large Steps in Cloth Simulation", section 5), with
// P = u u^T and vr = v_a - v_b:
//     df_a/dx_a = -ks [ P + (1 - l0/l)(I - P) ]  -  kd/l [ (vr.u) (I - P) + u vr^T (I - P) ]
//     df_a/dv_a = -kd P
// and by f_b = -f_a and the dependence on x_a - x_b only:
//     df_a/dx_b = -df_a/dx_a,  df_b/dx_a = -df_a/dx_a,  df_b/dx_b = df_a/dx_a  (same for dv).
// The stiffness part is symmetric; the damper's position term is not (Baraff & Witkin drop
// it to keep the system symmetric). Both are returned so the solver can choose.
#pragma once

#include <Eigen/Core>

namespace clothsim {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Force on a. A zero-length spring has no direction: returns zero rather than NaN.
inline Vec3 spring_damper_force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                                double rest, double ks, double kd) {
  const Vec3 d = xa - xb;
  const double l = d.norm();
  if (l <= 0.0) return Vec3::Zero();
  const Vec3 u = d / l;
  return (-ks * (l - rest) - kd * (va - vb).dot(u)) * u;
}

struct SpringJacobian {
  Mat3 dfdx_stiffness;  // symmetric stiffness part of df_a/dx_a
  Mat3 dfdx_damping;    // non-symmetric damper part of df_a/dx_a
  Mat3 dfdv;            // df_a/dv_a = -kd u u^T (symmetric)
  Mat3 dfdx() const { return dfdx_stiffness + dfdx_damping; }
};

SpringJacobian spring_damper_jacobian(const Vec3& xa, const Vec3& xb, const Vec3& va,
                                      const Vec3& vb, double rest, double ks, double kd);

// The spring-damper over one backward-Euler step of size h, as implicit_euler solves it.
// The damper's rate is the step's finite difference of the length, (l - ln) / h, with ln the
// length at the start of the step, in place of the instantaneous (v_a - v_b) . u:
//     f_a = -T u,   T = ks (l - l0) + (kd / h) (l - ln)        (tension, N)
// Then the force is minus the gradient of one potential of the end-of-step positions,
//     E = 0.5 ks (l - l0)^2 + (kd / 2h) (l - ln)^2,
// a spring of stiffness ks + kd/h about a blend of l0 and ln, so backward Euler becomes the
// minimisation of a scalar (Gast et al. 2015) with a symmetric Hessian. Its block for x_a is
//     K = (ks + kd/h) P + (T / l) (I - P),     P = u u^T,
// (df_a/dx_a = -K), positive semi-definite except across a spring whose tension is negative;
// projecting it (T / l clamped at 0) keeps every block PSD (Martin et al. 2011's per-element
// projection). The two damper rates agree to first order in h: the finite difference is the
// length rate averaged over the step, while u_{n+1} . (v_a - v_b)_{n+1} also counts a rigid
// rotation by theta as a shortening l (1 - cos theta), which the continuous damper does not.
inline double step_spring_tension(double l, double rest, double start_length, double ks,
                                  double kd, double h) {
  return ks * (l - rest) + (kd / h) * (l - start_length);
}
inline double step_spring_energy(double l, double rest, double start_length, double ks, double kd,
                                 double h) {
  const double stretch = l - rest, rate = l - start_length;
  return 0.5 * ks * stretch * stretch + 0.5 * (kd / h) * rate * rate;
}
// K above for the spring (a, b) at end-of-step separation d = x_a - x_b, as its parts:
// K = axial P + transverse (I - P), P = u u^T. A zero-length spring has no direction: an
// isotropic stand-in, K = (ks + kd/h) I.
struct StepSpringBlock {
  Vec3 u = Vec3::Zero();
  double axial = 0.0, transverse = 0.0;
  Mat3 matrix() const {  // closed form: no 3x3 products
    Mat3 K = (axial - transverse) * (u * u.transpose());
    K.diagonal().array() += transverse;
    return K;
  }
};
inline StepSpringBlock step_spring_block(const Vec3& d, double rest, double start_length,
                                         double ks, double kd, double h) {
  StepSpringBlock k;
  k.axial = ks + kd / h;
  const double l = d.norm();
  if (l <= 0.0) {
    k.transverse = k.axial;
    return k;
  }
  k.u = d / l;
  k.transverse = step_spring_tension(l, rest, start_length, ks, kd, h) / l;
  return k;
}
// K itself; with `project`, the transverse coefficient is clamped at 0 (the PSD projection).
inline Mat3 step_spring_hessian(const Vec3& d, double rest, double start_length, double ks,
                                double kd, double h, bool project) {
  StepSpringBlock k = step_spring_block(d, rest, start_length, ks, kd, h);
  if (project && k.transverse < 0.0) k.transverse = 0.0;
  return k.matrix();
}

// D -= alpha u u^T + beta I (a spring's block G in the Newton matrix's terms: sparse_system.h),
// written out on the symmetric block (6 distinct entries).
inline void subtract_block(Mat3& D, double alpha, double beta, const Vec3& u) {
  const double xx = alpha * u[0] * u[0] + beta, yy = alpha * u[1] * u[1] + beta,
               zz = alpha * u[2] * u[2] + beta;
  const double xy = alpha * u[0] * u[1], xz = alpha * u[0] * u[2], yz = alpha * u[1] * u[2];
  D(0, 0) -= xx;
  D(1, 1) -= yy;
  D(2, 2) -= zz;
  D(0, 1) -= xy;
  D(1, 0) -= xy;
  D(0, 2) -= xz;
  D(2, 0) -= xz;
  D(1, 2) -= yz;
  D(2, 1) -= yz;
}

// Potential energy 0.5 ks (l - l0)^2, J.
inline double spring_energy(const Vec3& xa, const Vec3& xb, double rest, double ks) {
  const double e = (xa - xb).norm() - rest;
  return 0.5 * ks * e * e;
}

}  // namespace clothsim
