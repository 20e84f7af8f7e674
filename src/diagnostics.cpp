#include "diagnostics.h"

#include <cmath>
#include <cstdio>

#include "spring_force.h"

namespace clothsim {

Energies compute_energies(const Model& model, const State& state) {
  Energies e;
  for (int b = 0; b < model.num_bodies(); ++b) {
    if (!std::isfinite(model.mass[b])) continue;  // kinematic spheres carry no energy of ours
    e.kinetic += 0.5 * model.mass[b] * state.v.col(b).squaredNorm();
    if (model.gravity_on[b]) e.gravity -= model.mass[b] * model.gravity.dot(state.x.col(b));
  }
  const Springs& s = model.springs;
  for (std::size_t i = 0; i < s.size(); ++i)
    e.spring += spring_energy(state.x.col(s.a[i]), state.x.col(s.b[i]), s.rest[i], s.ks[i]);
  return e;
}

double max_strain(const Model& model, const State& state) {
  const Springs& s = model.springs;
  double worst = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double l = (state.x.col(s.a[i]) - state.x.col(s.b[i])).norm();
    const double strain = (l - s.rest[i]) / s.rest[i];
    if (!(strain <= worst)) worst = strain;  // also propagates NaN
  }
  return worst;
}

std::optional<Divergence> check_bodies(const Model& model, const State& state) {
  const auto diverged = [&](const char* what, int body) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s (body %d)", what, body);
    return std::optional<Divergence>(Divergence{state.step, state.t, buf});
  };
  double kinetic = 0.0, gravity = 0.0;
  for (int b = 0; b < model.num_bodies(); ++b) {
    if (!state.x.col(b).allFinite()) return diverged("non-finite position", b);
    if (!state.v.col(b).allFinite()) return diverged("non-finite velocity", b);
    if (!std::isfinite(model.mass[b])) continue;  // kinematic spheres carry no energy of ours
    kinetic += 0.5 * model.mass[b] * state.v.col(b).squaredNorm();
    if (model.gravity_on[b]) gravity -= model.mass[b] * model.gravity.dot(state.x.col(b));
  }
  // Finite values can still sum to an infinite energy (gravity of 1e308 on a resting cloth).
  const auto whole = [&](const char* what) {
    return std::optional<Divergence>(Divergence{state.step, state.t, what});
  };
  if (!std::isfinite(kinetic)) return whole("non-finite kinetic energy");
  if (!std::isfinite(gravity)) return whole("non-finite gravitational energy");
  const double bound = model.divergence.max_energy_factor * model.energy_scale;
  if (kinetic > bound) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "kinetic energy %.3g J exceeds the bound %.3g J", kinetic, bound);
    return std::optional<Divergence>(Divergence{state.step, state.t, buf});
  }
  return std::nullopt;
}

std::optional<Divergence> check_strain(const Model& model, double strain, std::int64_t step,
                                       double t) {
  if (strain <= model.divergence.max_strain) return std::nullopt;  // NaN falls through
  char buf[160];
  std::snprintf(buf, sizeof buf, "spring strain %.3g exceeds the bound %.3g", strain,
                model.divergence.max_strain);
  return Divergence{step, t, buf};
}

std::optional<Divergence> check_divergence(const Model& model, const State& state) {
  if (auto bad = check_bodies(model, state)) return bad;
  return check_strain(model, max_strain(model, state), state.step, state.t);
}

}  // namespace clothsim
