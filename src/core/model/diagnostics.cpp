#include "diagnostics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "core/model/barrier_contacts.h"
#include "core/springs/spring_force.h"

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
  e.contact = barrier_potential(model, state.x);  // 0 under collision.model: projection
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

namespace {

// Adding one to a double's exponent field carries into the sign bit exactly when every
// exponent bit is set: for infinities and NaNs, and only for them. OR-ed over values, the
// sign bit says whether any was not finite, with no comparison or branch per value.
constexpr std::uint64_t kExponent = 0x7ff0000000000000u, kExponentOne = 0x0010000000000000u;
inline std::uint64_t exponent_carry(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return (bits & kExponent) + kExponentOne;
}

}  // namespace

std::optional<Divergence> check_bodies(const Model& model, const State& state) {
  const auto diverged = [&](const char* what, int body) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s (body %d)", what, body);
    return std::optional<Divergence>(Divergence{state.step, state.t, buf});
  };
  // One pass over the bodies' coordinates: their finiteness (exponent_carry) and the energies.
  // The body to name is searched for only when some value is not finite. (Tested a column at
  // a time with Eigen's allFinite, and the energies summed through per-column expressions,
  // this check cost an explicit Euler step of 25 x 25 a fifth of its time.)
  double kinetic = 0.0, gravity = 0.0;
  std::uint64_t carried = 0;
  const double g[3] = {model.gravity.x(), model.gravity.y(), model.gravity.z()};
  const double* px = state.x.data();
  const double* pv = state.v.data();
  for (int b = 0; b < model.num_bodies(); ++b) {
    const double* x = px + 3 * static_cast<std::ptrdiff_t>(b);
    const double* v = pv + 3 * static_cast<std::ptrdiff_t>(b);
    for (int k = 0; k < 3; ++k) carried |= exponent_carry(x[k]) | exponent_carry(v[k]);
    const double m = model.mass[b];
    if (!std::isfinite(m)) continue;  // kinematic spheres carry no energy of ours
    kinetic += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (model.gravity_on[b]) gravity -= m * (g[0] * x[0] + g[1] * x[1] + g[2] * x[2]);
  }
  if (carried >> 63)
    for (int b = 0; b < model.num_bodies(); ++b) {
      if (!state.x.col(b).allFinite()) return diverged("non-finite position", b);
      if (!state.v.col(b).allFinite()) return diverged("non-finite velocity", b);
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

bool external_work(const Model& model, const State& state) {
  for (int b = 0; b < model.num_bodies(); ++b)
    if (state.inv_mass[b] == 0.0 && state.v.col(b).squaredNorm() > 0.0) return true;
  return false;
}

void record_energy(EnergyLedger& ledger, double energy, bool work) {
  if (!std::isfinite(energy)) return;
  if (work || !(energy >= ledger.lowest)) ledger.lowest = energy;  // NaN: the first sample
  ledger.rise = energy - ledger.lowest;
}

std::optional<Divergence> check_energy_made(const Model& model, const EnergyLedger& ledger,
                                            std::int64_t step, double t) {
  const double bound = kWrongEnergyRise * model.energy_scale;
  if (!(ledger.rise > bound)) return std::nullopt;
  char buf[200];
  // Short enough for a tile's three-line banner; the bound's rule is in docs/integrators.md.
  std::snprintf(buf, sizeof buf, "energy rose %.3g J with no work done (bound %.3g J)", ledger.rise, bound);
  return Divergence{step, t, buf};
}

std::optional<Divergence> check_over_stretched(double strain, double start_strain, std::int64_t step,
                                               double t) {
  const double bound = std::max(start_strain, 0.0) + kWrongStrain;
  if (!(strain > bound)) return std::nullopt;  // NaN is divergence's to report
  // Three figures, or as many as tell the strain from its bound ("strain 1.0012 past the bound
  // 1", not "strain 1 past the bound 1").
  char s[32], b[32];
  int digits = 3;
  do {
    std::snprintf(s, sizeof s, "%.*g", digits, strain);
    std::snprintf(b, sizeof b, "%.*g", digits, bound);
  } while (std::strcmp(s, b) == 0 && ++digits <= 12);
  char buf[160];
  std::snprintf(buf, sizeof buf, "strain %s past the bound %s", s, b);
  return Divergence{step, t, buf};
}

}  // namespace clothsim
