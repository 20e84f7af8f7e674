// What a run reports about itself: energies, strain, and whether it has diverged.
#pragma once

#include <optional>
#include <string>

#include "model.h"
#include "state.h"

namespace clothsim {

struct Energies {
  double kinetic = 0.0;  // J, sum 0.5 m |v|^2 over movable bodies
  double spring = 0.0;   // J, sum 0.5 ks (l - l0)^2
  double gravity = 0.0;  // J, sum -m g . x over bodies gravity acts on
  double total() const { return kinetic + spring + gravity; }
};

Energies compute_energies(const Model& model, const State& state);

// Largest relative extension (l - l0) / l0 over all springs (0 with no springs).
double max_strain(const Model& model, const State& state);

struct Divergence {
  std::int64_t step = 0;
  double t = 0.0;       // s, time of the state found bad
  std::string reason;   // e.g. "non-finite position", "strain 12.3 > 10"
};

// Checks a state against the model's bounds: non-finite values (always), then strain and
// kinetic energy (when `full`, as they cost a pass over the springs).
std::optional<Divergence> check_divergence(const Model& model, const State& state, bool full);

}  // namespace clothsim
