// What a run reports about itself: energies, strain, and whether it has diverged.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "model.h"
#include "state.h"

namespace clothsim {

struct Energies {
  double kinetic = 0.0;  // J, sum 0.5 m |v|^2 over movable bodies
  double spring = 0.0;   // J, sum 0.5 ks (l - l0)^2
  double gravity = 0.0;  // J, sum -m g . x over bodies gravity acts on
  double contact = 0.0;  // J, the barrier's potential (collision.model: barrier; 0 otherwise)
  double total() const { return kinetic + spring + gravity + contact; }
};

Energies compute_energies(const Model& model, const State& state);

// Largest relative extension (l - l0) / l0 over all springs (0 with no springs).
double max_strain(const Model& model, const State& state);

struct Divergence {
  std::int64_t step = 0;
  double t = 0.0;       // s, time of the state found bad
  std::string reason;   // e.g. "non-finite position", "strain 12.3 > 10"
};

// Divergence is checked after every step, in two parts that together cost one pass over the
// bodies and none over the springs:
//  - check_bodies: non-finite positions or velocities, a non-finite kinetic or gravitational
//    energy, kinetic energy past max_energy_factor x the scene's energy scale;
//  - check_strain: a strain some force pass already measured (every integrator's first force
//    evaluation is at the state its step starts from, so a step reports the strain of that
//    state: a stretched state is found one step after it was reached, and reported with its
//    own step and time, so the result does not depend on when anything else looks).
std::optional<Divergence> check_bodies(const Model& model, const State& state);
std::optional<Divergence> check_strain(const Model& model, double strain, std::int64_t step,
                                       double t);
// Both, measuring the strain with a pass over the springs: for a state no force pass has
// seen (the end of a run, an output frame).
std::optional<Divergence> check_divergence(const Model& model, const State& state);

// WRONG: a run that stays finite but is not this scene's physics (docs/integrators.md,
// "WRONG"). Two stated bounds, the same for every method and every command:
//  - energy made: over a stretch in which nothing does work on the bodies (no immovable body
//    moves, no velocity is set), the total energy rose above the stretch's lowest sample by
//    more than kWrongEnergyRise x the scene's energy scale (Model::energy_scale). Damping,
//    drag and inelastic contact only take energy away, so a converged backward-Euler step
//    never gains it;
//  - over-stretched: a spring's strain passed kWrongStrain beyond the largest strain the scene
//    starts with (a cloth stretched to twice its rest length is no cloth).
// Energy is sampled every kWrongEnergyEvery simulated seconds (every step when the step is
// longer): one pass over the springs per sample, and samples at fixed steps, so every
// command sees the same verdict at the same step.
inline constexpr double kWrongEnergyRise = 0.02;
inline constexpr double kWrongStrain = 1.0;
inline constexpr double kWrongEnergyEvery = 1.0 / 60.0;  // s

// Whether something outside the bodies' forces does work at `state`: an immovable body (a
// kinematic sphere, a pinned particle) that moves.
bool external_work(const Model& model, const State& state);

// The energy samples of the current no-work stretch.
struct EnergyLedger {
  double lowest = std::numeric_limits<double>::quiet_NaN();  // J, lowest total since work was done
  double rise = 0.0;                                          // J, the last sample above it
};

// Adds a sample of the total energy (non-finite ones are ignored). `work`: something did work
// since the last sample, so the stretch starts again from this one.
void record_energy(EnergyLedger& ledger, double energy, bool work);

// The WRONG verdicts, pure: nullopt while within the bounds above.
std::optional<Divergence> check_energy_made(const Model& model, const EnergyLedger& ledger,
                                            std::int64_t step, double t);
std::optional<Divergence> check_over_stretched(double strain, double start_strain,
                                               std::int64_t step, double t);

}  // namespace clothsim
