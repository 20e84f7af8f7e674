#include "forces.h"

#include <cmath>
#include <cstddef>

#include "core/base/body_terms.h"
#include "core/model/barrier_contacts.h"
#include "core/springs/spring_force.h"
#include "core/springs/spring_kernels.h"

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
  if (model.spring_path() == SpringPath::List) return scalar_spring_pass(model.springs, x, v, f) - 1.0;
  const double ratio = accumulate_family_spring_forces(layout, x, v, f);
  return sticky_max(ratio, scalar_spring_pass(layout.others, x, v, f)) - 1.0;  // x - 1 is monotone
}

double accumulate_spring_forces_scalar(const Springs& springs, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  return scalar_spring_pass(springs, x, v, f) - 1.0;
}

BodyTermInputs body_term_inputs(const Model& model, const Eigen::Matrix3Xd& v, const Eigen::VectorXd& inv_mass,
                                bool times_inverse_mass) {
  BodyTermInputs in;
  in.mass = model.mass.data();
  in.inv_mass = inv_mass.data();
  in.gravity_on = model.gravity_on.data();
  in.v = v.data();
  in.bodies = static_cast<std::size_t>(model.num_bodies());
  in.particles = static_cast<std::size_t>(model.num_particles);
  in.drag = model.air_drag;
  for (int d = 0; d < 3; ++d) in.g[d] = model.gravity[d];
  in.times_inverse_mass = times_inverse_mass;
  return in;
}

namespace {

// Springs, then gravity, drag and (for accelerations) 1/m on every body. Where the SIMD
// families cover every spring, the kernel applies the body terms to each particle as it
// finishes it (no zeroing of f, no second pass over the bodies: together an eighth of a
// 25 x 25 evaluation in the scalar loop, `perf`) and the rest is done here; otherwise the
// springs are summed into a zeroed f and body_terms() runs on every body. The bits are the
// same either way (spring_kernels.h).
double forces_with_body_terms(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                              const Eigen::VectorXd& inv_mass, bool times_inverse_mass, Eigen::Matrix3Xd& f) {
  const BodyTermInputs in = body_term_inputs(model, v, inv_mass, times_inverse_mass);
  const SpringLayout& layout = model.spring_layout;
  std::size_t first = 0;  // bodies below it are done
  double strain;
  if (model.spring_path() == SpringPath::Families) {
    f.resize(3, model.num_bodies());
    strain = family_forces_with_body_terms(layout, x, v, in, f, first) - 1.0;
    f.rightCols(model.num_bodies() - static_cast<Eigen::Index>(first)).setZero();
  } else {
    f.setZero(3, model.num_bodies());
    strain = accumulate_spring_forces(model, x, v, f);
  }
  double* pf = f.data();
  for (std::size_t i = first; i < in.bodies; ++i) body_terms(in, i, pf + 3 * i);
  // The barrier is a force like the springs, in every evaluation (every stage of every method).
  if (uses_barrier(model)) add_barrier_forces(model, x, v, inv_mass, times_inverse_mass, f);
  return strain;
}

}  // namespace

double total_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                    const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& f) {
  return forces_with_body_terms(model, x, v, inv_mass, /*times_inverse_mass=*/false, f);
}

double accelerations(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                     const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& a) {
  return forces_with_body_terms(model, x, v, inv_mass, /*times_inverse_mass=*/true, a);  // a_i = f_i / m_i
}

}  // namespace clothsim
