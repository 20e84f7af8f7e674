#include "spring_force.h"

namespace clothsim {

SpringJacobian spring_damper_jacobian(const Vec3& xa, const Vec3& xb, const Vec3& va,
                                      const Vec3& vb, double rest, double ks, double kd) {
  SpringJacobian J;
  const Vec3 d = xa - xb;
  const double l = d.norm();
  if (l <= 0.0) {  // degenerate: no direction, treat as a plain isotropic spring of stiffness ks
    J.dfdx_stiffness = -ks * Mat3::Identity();
    J.dfdx_damping.setZero();
    J.dfdv = -kd / 3.0 * Mat3::Identity();
    return J;
  }
  const Vec3 u = d / l;
  const Mat3 P = u * u.transpose();          // projector onto the spring axis
  const Mat3 Q = Mat3::Identity() - P;       // projector across it; du/dd = Q / l
  const Vec3 vr = va - vb;
  // Hooke part: d/dd [-ks (l - l0) u] = -ks [u u^T + (l - l0) Q / l].
  J.dfdx_stiffness = -ks * (P + (1.0 - rest / l) * Q);
  // Damper part: d/dd [-kd (vr.u) u] = -kd [(vr.u) Q / l + u (vr^T Q / l)].
  J.dfdx_damping = -(kd / l) * (vr.dot(u) * Q + u * (vr.transpose() * Q));
  J.dfdv = -kd * P;
  return J;
}

}  // namespace clothsim
