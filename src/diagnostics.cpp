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

std::optional<Divergence> check_divergence(const Model& model, const State& state, bool full) {
  const auto diverged = [&](std::string reason) {
    return std::optional<Divergence>(Divergence{state.step, state.t, std::move(reason)});
  };
  if (!state.x.allFinite()) return diverged("non-finite position");
  if (!state.v.allFinite()) return diverged("non-finite velocity");
  if (!full) return std::nullopt;
  char buf[160];
  const double strain = max_strain(model, state);
  if (strain > model.divergence.max_strain) {
    std::snprintf(buf, sizeof buf, "spring strain %.3g exceeds the bound %.3g", strain,
                  model.divergence.max_strain);
    return diverged(buf);
  }
  const double kinetic = compute_energies(model, state).kinetic;
  const double bound = model.divergence.max_energy_factor * model.energy_scale;
  if (kinetic > bound) {
    std::snprintf(buf, sizeof buf, "kinetic energy %.3g J exceeds the bound %.3g J", kinetic, bound);
    return diverged(buf);
  }
  return std::nullopt;
}

}  // namespace clothsim
