// The barrier contact model's kernels (collision.model: barrier): pure functions of values.
//
// A smooth conservative potential between a particle and a surface at distance d (the ground
// plane: d = y - height; a sphere: d = |x - c| - r), active within d-hat (IPC, Li et al. 2020):
//     b(d) = -kappa (d - dhat)^6 ln(d / dhat)   for 0 < d < dhat,   0 for d >= dhat,   +inf for d <= 0.
// IPC's own barrier has (d - dhat)^2: b ~ kappa (dhat - d)^3 / dhat where a contact activates,
// so its force b'(d) is only C1 there, a step across an activation errs by h^3, and RK4's
// global error falls as h^3 at best. With the power p, b ~ kappa (dhat - d)^(p+1) / dhat: the
// force is C(p-1), and a step across errs by h^(p+1) times the jump of the force's p-th time
// derivative, which is huge (kappa / dhat). p = 4 (C3) measured RK4 at 4.5 on the smooth drape
// (the activations' h^5 errors outweigh its own h^4 ones at every usable step); p = 6 (C5)
// measures 4 (BENCHMARKS.md). Convex on (0, dhat), decreasing, and b -> +inf as d -> 0: a
// method that keeps the energy finite never lets a distance reach zero.
//
// Stiffness, stated as the contact's stiffness at half its reach, k = b''(dhat / 2) in N/m
// (collision.barrier_stiffness), so kappa = k / (b''(dhat/2) at kappa = 1). Unset, it is chosen
// from the scene as IPC chooses kappa from the forces it must balance: so that a particle of the
// cloth's mean mass resting on a surface under gravity alone sits at d = dhat / 2,
//     -b'(dhat / 2) = m g   (g = |gravity|, 9.8 m/s^2 where the scene has none).
//
// Friction (IPC's lagged, smoothed Coulomb): the tangential force -mu lambda f1(|u|) u / |u| on
// the tangential relative velocity (or displacement over the step) u, lambda the normal force
// -b'(d) and f1 the mollifier 2 s / eps - s^2 / eps^2 for s < eps, 1 beyond (C1 at s = eps).
// The explicit methods evaluate it at each stage's (x, v); implicit_euler and vbd take lambda
// and the tangent at the step's start (lagged) and the displacement through the potential
//     D(u) = mu lambda f0(|u|),  f0(s) = -s^3 / (3 eps^2) + s^2 / eps + eps / 3 (s < eps), s beyond,
// with eps = eps_v h (collision.friction_velocity), whose gradient is that force.
#pragma once

#include <Eigen/Core>

namespace clothsim {

using BarrierVec3 = Eigen::Vector3d;
using BarrierMat3 = Eigen::Matrix3d;

constexpr int kBarrierPower = 6;  // p above

struct BarrierParams {
  double dhat = 0.0;   // m, where the barrier activates
  double kappa = 0.0;  // J/m^4, b's multiplier
};

// b(d), b'(d), b''(d): above. 0 at d >= dhat; b = +inf, b' = -inf, b'' = +inf at d <= 0.
double barrier_energy(double d, const BarrierParams& p);
double barrier_derivative(double d, const BarrierParams& p);
double barrier_second_derivative(double d, const BarrierParams& p);

// kappa from the stiffness at half the reach, k = b''(dhat / 2) (N/m).
double barrier_kappa_for_stiffness(double stiffness, double dhat);
// The stiffness k whose barrier holds a weight w (N) at d = dhat / 2: -b'(dhat / 2) = w.
double barrier_stiffness_for_weight(double weight, double dhat);

// One particle against one surface: the barrier's energy, its gradient with respect to the
// particle's position and its Hessian there (3x3). For a sphere the collider's centre gets the
// opposite gradient and the same Hessian with the sign of the cross blocks flipped.
struct PointBarrier {
  double distance = 0.0;                        // m, d
  double energy = 0.0;                          // J
  BarrierVec3 normal = BarrierVec3::UnitY();    // unit, out of the collider
  BarrierVec3 gradient = BarrierVec3::Zero();   // N (= -force on the particle)
  BarrierMat3 hessian = BarrierMat3::Zero();    // N/m
  bool active() const { return energy != 0.0; }
};

// The ground plane y = height. Hessian b'' n n^T (always PSD).
PointBarrier plane_barrier(const BarrierVec3& x, double height, const BarrierParams& p);
// A sphere of radius r centred at c. Hessian b'' n n^T + b' (I - n n^T) / |x - c|; with
// `project_psd`, the transverse term (negative, as b' < 0) clamped at 0: the PSD projection
// that Newton and VBD's 3x3 solves use (Li et al. 2020, per contact).
PointBarrier sphere_barrier(const BarrierVec3& x, const BarrierVec3& c, double r, const BarrierParams& p,
                            bool project_psd);

// The largest alpha in [0, 1] such that moving along x + alpha dx keeps the distance at or above
// `keep` times its value at alpha = 0 (keep in [0, 1)): closed form for a line against a plane
// and against a sphere (the first root of a quadratic). 1 where the motion never gets closer.
double plane_step_bound(double gap, double dgap, double keep);
double sphere_step_bound(const BarrierVec3& relative, const BarrierVec3& drelative, double r, double keep);

// IPC's friction mollifier f1 (above) at speed s with threshold eps, and f1(s) / s (finite at 0).
double friction_f1(double s, double eps);
double friction_f1_over_s(double s, double eps);
// f0, the potential whose derivative is f1 (f0(0) = eps / 3).
double friction_f0(double s, double eps);

// The smoothed Coulomb force on tangential relative velocity vt (3-vector, already tangential):
// -mu lambda f1(|vt|) vt / |vt|, with eps = eps_v.
BarrierVec3 friction_force(const BarrierVec3& vt, double lambda, double mu, double eps_v);

// The lagged friction potential on the tangential displacement u (3-vector in the tangent
// plane of normal n): D = mu lambda f0(|u|), its gradient mu lambda f1(|u|) u / |u|, and its
// Hessian projected to the tangent plane (PSD: IPC's form), all with eps = eps_v h.
struct FrictionTerm {
  double energy = 0.0;
  BarrierVec3 gradient = BarrierVec3::Zero();
  BarrierMat3 hessian = BarrierMat3::Zero();
};
FrictionTerm friction_potential(const BarrierVec3& u, const BarrierVec3& n, double lambda, double mu, double eps);

}  // namespace clothsim
