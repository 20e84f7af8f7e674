#include "integrators/step_potential.h"

#include <cmath>

#include "spring_force.h"

namespace clothsim {

double spring_lengths(const Springs& springs, const Eigen::Matrix3Xd& x,
                      std::vector<double>& length) {
  length.resize(springs.size());
  double worst = 0.0;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    length[s] = (x.col(springs.a[s]) - x.col(springs.b[s])).norm();
    const double strain = length[s] / springs.rest[s] - 1.0;
    if (!(strain <= worst)) worst = strain;  // also propagates NaN
  }
  return worst;
}

PotentialValue step_potential(const Model& model, const State& start, double h,
                              const std::vector<double>& start_length, const Eigen::Matrix3Xd& dv,
                              Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient) {
  const int B = model.num_bodies();
  const Eigen::VectorXd& w = start.inv_mass;
  y.noalias() = start.x + h * (start.v + dv);
  gradient.setZero(3, B);
  PotentialValue value;

  // Springs: E_s at y; dE_s/dy_a = T u, so dE_s/ddv_a = h T u (and -h T u for b).
  const Springs& springs = model.springs;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = springs.a[s], b = springs.b[s];
    const Vec3 d = y.col(a) - y.col(b);
    const double l = d.norm();
    const double e = step_spring_energy(l, springs.rest[s], start_length[s], springs.ks[s],
                                        springs.kd[s], h);
    value.phi += e;
    value.magnitude += e;
    if (l <= 0.0) continue;  // no direction: no force (as the force pass)
    const double T = step_spring_tension(l, springs.rest[s], start_length[s], springs.ks[s],
                                         springs.kd[s], h);
    // E is a square of a difference of lengths (l - l0), each known to eps l: its rounding
    // is about |T| eps l, far above eps E for a spring near its rest length.
    value.magnitude += std::abs(T) * l;
    const Vec3 push = (h * T / l) * d;
    gradient.col(a) += push;
    gradient.col(b) -= push;
  }

  // Bodies: inertia, gravity and drag; immovable bodies are not unknowns.
  const double drag = model.air_drag;
  for (int i = 0; i < B; ++i) {
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
      const double dissipation = 0.5 * h * drag * v.squaredNorm();
      value.phi += dissipation;
      value.magnitude += dissipation;
      gradient.col(i) += (h * drag) * v;
    }
  }
  return value;
}

}  // namespace clothsim
