#include "step_potential.h"

#include <cmath>

#include "barrier_terms.h"
#include "potential_kernels.h"
#include "core/model/barrier_contacts.h"
#include "core/springs/spring_force.h"
#include "core/springs/spring_kernels.h"  // sticky_max

namespace clothsim {

namespace {

// The largest l / l0 over springs [0, n) of `springs`, lengths written to length[slot(s)].
// The ratio rather than the strain, so the scalar and SIMD passes combine exactly (rounding is
// monotone: max(l / l0) - 1 is max(l / l0 - 1)); a NaN sticks.
template <class Slot>
double scalar_lengths(const Springs& springs, const Eigen::Matrix3Xd& x, double* length,
                      const Slot& slot) {
  double worst = 1.0;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const double l = (x.col(springs.a[s]) - x.col(springs.b[s])).norm();
    length[slot(s)] = l;
    worst = sticky_max(worst, l / springs.rest[s]);
  }
  return worst;
}

// Phi's terms of springs [0, n), reference lengths at start_length[slot(s)]: E_s at y;
// dE_s/dy_a = T u, so dE_s/ddv_a = h T u (and -h T u for b), T's damper rate over damper_h.
template <class Slot>
void add_spring_terms(const Springs& springs, const double* start_length, const Slot& slot,
                      const StepForm& form, const Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient,
                      PotentialValue& value) {
  const double h = form.h, damper_h = form.damper_h;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = springs.a[s], b = springs.b[s];
    const double ln = start_length[slot(s)];
    const Vec3 d = y.col(a) - y.col(b);
    const double l = d.norm();
    const double e = step_spring_energy(l, springs.rest[s], ln, springs.ks[s], springs.kd[s], damper_h);
    value.phi += e;
    value.magnitude += e;
    if (l <= 0.0) continue;  // no direction: no force (as the force pass)
    const double T = step_spring_tension(l, springs.rest[s], ln, springs.ks[s], springs.kd[s], damper_h);
    // E is a square of a difference of lengths (l - l0), each known to eps l: its rounding
    // is about |T| eps l, far above eps E for a spring near its rest length.
    value.magnitude += std::abs(T) * l;
    const Vec3 push = (h * T / l) * d;
    gradient.col(a) += push;
    gradient.col(b) -= push;
  }
}

// Bodies: inertia, gravity and drag; immovable bodies are not unknowns.
void add_body_terms(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& dv,
                    Eigen::Matrix3Xd& gradient, PotentialValue& value) {
  const double h = form.h, drag_h = form.drag_h;
  const Eigen::VectorXd& w = start.inv_mass;
  const double drag = model.air_drag;
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (w[i] == 0.0) {
      gradient.col(i).setZero();
      continue;
    }
    const double m = 1.0 / w[i];
    const Vec3 v = start.v.col(i) + dv.col(i);
    const double inertia = 0.5 * m * dv.col(i).squaredNorm();
    value.phi += inertia;
    value.magnitude += inertia;
    gradient.col(i) += m * dv.col(i);
    if (model.gravity_on[i]) {
      const double work = h * m * model.gravity.dot(v);  // -Phi's gravity term
      value.phi -= work;
      value.magnitude += std::abs(work);
      gradient.col(i) -= (h * m) * model.gravity;
    }
    if (i < model.num_particles && drag != 0.0) {
      const double dissipation = 0.5 * drag_h * drag * v.squaredNorm();
      value.phi += dissipation;
      value.magnitude += dissipation;
      gradient.col(i) += (drag_h * drag) * v;
    }
  }
}

}  // namespace

double spring_lengths(const Springs& springs, const Eigen::Matrix3Xd& x,
                      std::vector<double>& length) {
  length.resize(springs.size());
  return scalar_lengths(springs, x, length.data(), [](std::size_t s) { return s; }) - 1.0;
}

double step_lengths(const Model& model, const Eigen::Matrix3Xd& x, std::vector<double>& length) {
  const SpringLayout& layout = model.spring_layout;
  if (model.spring_path() == SpringPath::List) return spring_lengths(model.springs, x, length);
  length.resize(layout.num_slots);
  const double families = family_step_lengths(layout, x, length.data());
  const double others = scalar_lengths(layout.others, x, length.data() + layout.others_first,
                                       [](std::size_t s) { return s; });
  return sticky_max(families, others) - 1.0;
}

double step_strain(const Model& model, const std::vector<double>& length) {
  return family_strain(model.spring_layout, length.data()) - 1.0;
}

PotentialValue step_potential(const Model& model, const State& start, const StepForm& form,
                              const std::vector<double>& start_length, const Eigen::Matrix3Xd& dv,
                              Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient,
                              std::vector<double>* end_length) {
  const double h = form.h;
  const SpringLayout& layout = model.spring_layout;
  double* lengths = nullptr;
  if (end_length) {
    if (model.spring_path() == SpringPath::Families) {
      end_length->resize(layout.num_slots);  // (the gaps stay zero, as step_lengths leaves them)
      lengths = end_length->data();
    } else {
      end_length->clear();
    }
  }
  if (model.spring_path() == SpringPath::List)
    return step_potential_scalar(model, start, form, start_length, dv, y, gradient);
  // The bodies first (y, and the gradient's first terms: body_terms in SIMD, the reference's
  // add_body_terms lane by lane), then the springs add theirs.
  BodyArgs bodies{start.x.data(), start.v.data(), dv.data(), start.inv_mass.data(), model.gravity_on.data()};
  bodies.bodies = static_cast<std::size_t>(model.num_bodies());
  bodies.particles = static_cast<std::size_t>(model.air_drag != 0.0 ? model.num_particles : 0);
  bodies.h = h;
  bodies.drag = model.air_drag;
  bodies.drag_h = form.drag_h;
  for (int c = 0; c < 3; ++c) bodies.gravity[c] = model.gravity[c];
  const FamilyPotential body = body_terms(bodies, y, gradient);
  const FamilyPotential families = family_step_potential(layout, y, start_length.data(), form, gradient, lengths);
  PotentialValue value;
  value.phi = families.phi + body.phi;
  value.magnitude = families.magnitude + body.magnitude;
  add_spring_terms(layout.others, start_length.data() + layout.others_first,
                   [](std::size_t s) { return s; }, form, y, gradient, value);
  if (uses_barrier(model)) add_barrier_potential(model, start, form, y, gradient, value);
  // Immovable bodies are not unknowns: no gradient there (the springs added theirs).
  const Eigen::VectorXd& w = start.inv_mass;
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (w[i] == 0.0) gradient.col(i).setZero();
  return value;
}

PotentialValue step_potential_scalar(const Model& model, const State& start, const StepForm& form,
                                     const std::vector<double>& start_length,
                                     const Eigen::Matrix3Xd& dv, Eigen::Matrix3Xd& y,
                                     Eigen::Matrix3Xd& gradient) {
  const double h = form.h;
  y.noalias() = start.x + h * (start.v + dv);
  gradient.setZero(3, model.num_bodies());
  PotentialValue value;
  const SpringLayout& layout = model.spring_layout;
  if (model.spring_path() != SpringPath::List) {
    add_spring_terms(model.springs, start_length.data(), [&](std::size_t s) { return layout.slot[s]; },
                     form, y, gradient, value);
  } else {
    add_spring_terms(model.springs, start_length.data(), [](std::size_t s) { return s; }, form, y,
                     gradient, value);
  }
  if (uses_barrier(model)) add_barrier_potential(model, start, form, y, gradient, value);
  add_body_terms(model, start, form, dv, gradient, value);  // (zeroes immovable bodies' gradient)
  return value;
}

}  // namespace clothsim
