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

// Potential energy 0.5 ks (l - l0)^2, J.
inline double spring_energy(const Vec3& xa, const Vec3& xb, double rest, double ks) {
  const double e = (xa - xb).norm() - rest;
  return 0.5 * ks * e * e;
}

}  // namespace clothsim
