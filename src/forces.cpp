#include "forces.h"

#include <cmath>
#include <cstddef>

#include "spring_force.h"
#include "spring_kernels.h"

namespace clothsim {

namespace {

// The reference loop; returns the largest l / l0 (1 when nothing is stretched). Springs are
// streamed as a structure of arrays; the kernel is written out (rather than calling
// spring_damper_force) so that the compiler keeps everything in registers and the one sqrt
// and one division per spring are explicit.
double scalar_spring_pass(const Springs& springs, const Eigen::Matrix3Xd& x,
                          const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  const std::size_t n = springs.size();
  const std::int32_t* ia = springs.a.data();
  const std::int32_t* ib = springs.b.data();
  const double* rest = springs.rest.data();
  const double* ks = springs.ks.data();
  const double* kd = springs.kd.data();
  const double* px = x.data();
  const double* pv = v.data();
  double* pf = f.data();
  double ratio = 1.0;  // largest l / l0 so far; the division runs only when it grows
  for (std::size_t s = 0; s < n; ++s) {
    const std::size_t a = 3 * static_cast<std::size_t>(ia[s]);
    const std::size_t b = 3 * static_cast<std::size_t>(ib[s]);
    const double dx = px[a] - px[b], dy = px[a + 1] - px[b + 1], dz = px[a + 2] - px[b + 2];
    const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
    // l / l0 can exceed ratio only if l >= ratio l0 (rounding is monotone), so the division
    // runs only then and the result is the exact maximum of the rounded l / l0, whatever the
    // order of the springs (the SIMD kernel returns the same number). A NaN length enters
    // and sticks: every later comparison with a NaN ratio is false.
    if ((l > 0.0 && l >= ratio * rest[s]) || l != l) {
      const double r = l / rest[s];
      if (!(r <= ratio)) ratio = r;
    }
    if (l <= 0.0) continue;  // coincident particles: no direction, no force (as the kernel)
    const double inv_l = 1.0 / l;
    const double ux = dx * inv_l, uy = dy * inv_l, uz = dz * inv_l;
    const double vrel = (pv[a] - pv[b]) * ux + (pv[a + 1] - pv[b + 1]) * uy +
                        (pv[a + 2] - pv[b + 2]) * uz;
    // f_a = (-ks (l - l0) - kd (vr . u)) u, f_b = -f_a (the seed's formula).
    const double mag = -ks[s] * (l - rest[s]) - kd[s] * vrel;
    const double fx = mag * ux, fy = mag * uy, fz = mag * uz;
    pf[a] += fx;
    pf[a + 1] += fy;
    pf[a + 2] += fz;
    pf[b] -= fx;
    pf[b + 1] -= fy;
    pf[b + 2] -= fz;
  }
  return ratio;
}

}  // namespace

double accumulate_spring_forces(const Model& model, const Eigen::Matrix3Xd& x,
                                const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  const SpringLayout& layout = model.spring_layout;
  if (!layout.covers(model.springs.size())) return scalar_spring_pass(model.springs, x, v, f) - 1.0;
  const double ratio = accumulate_family_spring_forces(layout, x, v, f);
  return sticky_max(ratio, scalar_spring_pass(layout.others, x, v, f)) - 1.0;  // x - 1 is monotone
}

double accumulate_spring_forces_scalar(const Springs& springs, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  return scalar_spring_pass(springs, x, v, f) - 1.0;
}

namespace {

// After the spring pass: gravity m g on bodies with gravity, drag -c v on cloth particles,
// zero on immovable bodies and, for accelerations, each body's sum times its inverse mass.
// One pass over plain arrays: written as per-column Eigen expressions of three doubles, with
// a second pass for the masses, this cost a 25 x 25 force evaluation a seventh of its time.
// The operations and their order are those of the column expressions, so the bits are too.
template <bool kTimesInverseMass>
void add_body_forces(const Model& model, const Eigen::Matrix3Xd& v, const Eigen::VectorXd& inv_mass,
                     Eigen::Matrix3Xd& f) {
  const int B = model.num_bodies(), P = model.num_particles;
  const double drag = model.air_drag;
  const double g[3] = {model.gravity.x(), model.gravity.y(), model.gravity.z()};
  const double* pv = v.data();
  double* pf = f.data();
  for (int i = 0; i < B; ++i) {
    double* fi = pf + 3 * static_cast<std::ptrdiff_t>(i);
    const double w = inv_mass[i];
    // In registers, stored once: storing each step and reloading stalls on store forwarding.
    double fx = 0.0, fy = 0.0, fz = 0.0;  // pinned particle or kinematic sphere: filtered
    if (w != 0.0) {
      fx = fi[0], fy = fi[1], fz = fi[2];
      if (model.gravity_on[i]) {
        const double m = model.mass[i];
        fx += m * g[0], fy += m * g[1], fz += m * g[2];
      }
      if (i < P && drag != 0.0) {  // air acts on cloth
        const double* vi = pv + 3 * static_cast<std::ptrdiff_t>(i);
        fx -= drag * vi[0], fy -= drag * vi[1], fz -= drag * vi[2];
      }
      if constexpr (kTimesInverseMass) fx *= w, fy *= w, fz *= w;
    }
    fi[0] = fx, fi[1] = fy, fi[2] = fz;
  }
}

}  // namespace

double total_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                    const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& f) {
  f.setZero(3, model.num_bodies());
  const double strain = accumulate_spring_forces(model, x, v, f);
  add_body_forces<false>(model, v, inv_mass, f);
  return strain;
}

double accelerations(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                     const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& a) {
  a.setZero(3, model.num_bodies());
  const double strain = accumulate_spring_forces(model, x, v, a);
  add_body_forces<true>(model, v, inv_mass, a);  // a_i = f_i / m_i, 0 where immovable
  return strain;
}

}  // namespace clothsim
