#include "barrier_kernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// s^n by multiplications (std::pow with a double exponent costs a force pass several times over).
inline double power(double s, int n) {
  double r = 1.0;
  for (int i = 0; i < n; ++i) r *= s;
  return r;
}
}  // namespace

// With s = dhat - d, L = ln(d / dhat) (< 0 inside the reach) and p = kBarrierPower:
//     b = -kappa s^p L,   b' = kappa s^(p-1) (p L - s / d),   b'' = kappa s^(p-2) (-p (p-1) L + 2 p s / d + s^2 / d^2).
double barrier_energy(double d, const BarrierParams& p) {
  if (d >= p.dhat) return 0.0;
  if (!(d > 0.0)) return kInf;
  const double s = p.dhat - d;
  return -p.kappa * power(s, kBarrierPower) * std::log(d / p.dhat);
}

double barrier_derivative(double d, const BarrierParams& p) {
  if (d >= p.dhat) return 0.0;
  if (!(d > 0.0)) return -kInf;
  const double s = p.dhat - d;
  return p.kappa * power(s, kBarrierPower - 1) * (kBarrierPower * std::log(d / p.dhat) - s / d);
}

double barrier_second_derivative(double d, const BarrierParams& p) {
  if (d >= p.dhat) return 0.0;
  if (!(d > 0.0)) return kInf;
  const double s = p.dhat - d, q = s / d;
  constexpr double n = kBarrierPower;
  return p.kappa * power(s, kBarrierPower - 2) * (-n * (n - 1.0) * std::log(d / p.dhat) + 2.0 * n * q + q * q);
}

double barrier_kappa_for_stiffness(double stiffness, double dhat) {
  return stiffness / barrier_second_derivative(0.5 * dhat, {dhat, 1.0});
}

double barrier_stiffness_for_weight(double weight, double dhat) {
  const BarrierParams unit{dhat, 1.0};
  return weight * barrier_second_derivative(0.5 * dhat, unit) / -barrier_derivative(0.5 * dhat, unit);
}

PointBarrier plane_barrier(const BarrierVec3& x, double height, const BarrierParams& p) {
  PointBarrier out;
  out.distance = x.y() - height;
  if (out.distance >= p.dhat) return out;
  const double d = out.distance;
  out.energy = barrier_energy(d, p);
  out.gradient = barrier_derivative(d, p) * out.normal;
  out.hessian(1, 1) = barrier_second_derivative(d, p);
  return out;
}

PointBarrier sphere_barrier(const BarrierVec3& x, const BarrierVec3& c, double r, const BarrierParams& p,
                            bool project_psd) {
  PointBarrier out;
  const BarrierVec3 rel = x - c;
  const double rho = rel.norm();
  out.distance = rho - r;
  if (out.distance >= p.dhat) return out;
  out.normal = rho > 0.0 ? BarrierVec3(rel / rho) : BarrierVec3(BarrierVec3::UnitY());
  const double d = out.distance;
  out.energy = barrier_energy(d, p);
  const double b1 = barrier_derivative(d, p), b2 = barrier_second_derivative(d, p);
  out.gradient = b1 * out.normal;
  const BarrierMat3 nn = out.normal * out.normal.transpose();
  // grad^2 d = (I - n n^T) / rho: the surface curves away, so the transverse term b' / rho < 0.
  const double transverse = project_psd ? 0.0 : b1 / rho;
  out.hessian = b2 * nn + transverse * (BarrierMat3::Identity() - nn);
  return out;
}

double plane_step_bound(double gap, double dgap, double keep) {
  if (!(gap > 0.0) || dgap >= 0.0) return 1.0;
  return std::min(1.0, (1.0 - keep) * gap / -dgap);
}

// |p + alpha q|^2 = R^2 with R = r + keep (|p| - r): a alpha^2 + b alpha + c = 0, c > 0; its
// smaller root, where the motion first reaches R, in the cancellation-free form 2c / (-b + sqrt).
double sphere_step_bound(const BarrierVec3& relative, const BarrierVec3& drelative, double r, double keep) {
  const double rho = relative.norm();
  if (!(rho > r)) return 1.0;
  const double R = r + keep * (rho - r);
  const double a = drelative.squaredNorm(), b = 2.0 * relative.dot(drelative), c = rho * rho - R * R;
  const double disc = b * b - 4.0 * a * c;
  if (a == 0.0 || b >= 0.0 || disc < 0.0) return 1.0;
  return std::min(1.0, 2.0 * c / (-b + std::sqrt(disc)));
}

double friction_f1(double s, double eps) { return s >= eps ? 1.0 : s * (2.0 / eps - s / (eps * eps)); }

double friction_f1_over_s(double s, double eps) { return s >= eps ? 1.0 / s : 2.0 / eps - s / (eps * eps); }

double friction_f0(double s, double eps) {
  return s >= eps ? s : -s * s * s / (3.0 * eps * eps) + s * s / eps + eps / 3.0;
}

BarrierVec3 friction_force(const BarrierVec3& vt, double lambda, double mu, double eps_v) {
  if (mu <= 0.0 || lambda <= 0.0) return BarrierVec3::Zero();
  return -(mu * lambda * friction_f1_over_s(vt.norm(), eps_v)) * vt;
}

// grad^2 D = mu lambda [f1'(s) u^ u^T + (f1(s) / s) (P - u^ u^T)], P = I - n n^T the tangent
// projector: f1' = 2/eps - 2s/eps^2 >= 0 below eps and 0 beyond, f1 / s > 0, so PSD.
FrictionTerm friction_potential(const BarrierVec3& u, const BarrierVec3& n, double lambda, double mu, double eps) {
  FrictionTerm out;
  if (mu <= 0.0 || lambda <= 0.0) return out;
  const double scale = mu * lambda, s = u.norm();
  const BarrierMat3 P = BarrierMat3::Identity() - n * n.transpose();
  const double f1_s = friction_f1_over_s(s, eps);
  out.energy = scale * friction_f0(s, eps);
  out.gradient = scale * f1_s * u;
  out.hessian = scale * f1_s * P;
  if (s > 0.0) {
    const BarrierVec3 uh = u / s;
    const double f1_prime = s >= eps ? 0.0 : 2.0 / eps - 2.0 * s / (eps * eps);
    out.hessian += scale * (f1_prime - f1_s) * (uh * uh.transpose());
  }
  return out;
}

}  // namespace clothsim
