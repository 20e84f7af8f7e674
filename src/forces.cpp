#include "forces.h"

#include <cmath>

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

double total_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                    const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& f) {
  const int B = model.num_bodies();
  f.setZero(3, B);
  const double strain = accumulate_spring_forces(model, x, v, f);
  const double drag = model.air_drag;
  for (int i = 0; i < B; ++i) {
    if (inv_mass[i] == 0.0) {  // pinned particle or kinematic sphere: filtered
      f.col(i).setZero();
      continue;
    }
    if (model.gravity_on[i]) f.col(i) += model.mass[i] * model.gravity;
    if (i < model.num_particles && drag != 0.0) f.col(i) -= drag * v.col(i);  // air acts on cloth
  }
  return strain;
}

double accelerations(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                     const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& a) {
  const double strain = total_forces(model, x, v, inv_mass, a);
  a.array().rowwise() *= inv_mass.transpose().array();  // a_i = f_i / m_i, 0 where immovable
  return strain;
}

}  // namespace clothsim
