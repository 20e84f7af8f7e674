// Symplectic Euler against its theory: first order; on the undamped spring its step matrix
// has determinant 1 and trace 2 - (w h)^2, so it is stable (energy bounded, oscillating
// about a conserved modified energy) for w h < 2 and grows exponentially beyond.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::SymplecticEuler;

double max_of(const std::vector<double>& E, std::size_t from, std::size_t to) {
  return *std::max_element(E.begin() + from, E.begin() + to);
}

TEST(SymplecticEuler, ConvergesAtFirstOrderOnTheDampedSpring) {
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.01);
  for (double p : observed_orders(scene, kKind, h0, T)) EXPECT_NEAR(p, 1.0, 0.15);
}

TEST(SymplecticEuler, StaysBoundedJustBelowTwoOverOmega) {
  const Model model = undamped_spring_model();
  const int steps = 4000;
  const std::vector<double> E = energy_history(model, kKind, step_for(model, 1.9), steps);
  // The energy swings widely at w h = 1.9 (the invariant ellipse is long) but does not grow:
  // the second half of the run reaches no higher than the first.
  EXPECT_LE(max_of(E, steps / 2, E.size()), 1.02 * max_of(E, 0, steps / 2));
  EXPECT_LT(max_of(E, 0, E.size()), 100.0 * E.front());
}

TEST(SymplecticEuler, DivergesJustAboveTwoOverOmega) {
  // Eigenvalue -1.88 per step at w h = 2.1: 20 steps grow the amplitude ~3e5 times.
  const Model model = undamped_spring_model(1e-8);
  const std::vector<double> E = energy_history(model, kKind, step_for(model, 2.1), 20);
  EXPECT_GT(E.back(), 1e8 * E.front());
}

TEST(SymplecticEuler, KeepsEnergyInASmallBandOverManyPeriods) {
  const Model model = undamped_spring_model();
  const double wh = 0.05;
  const int per_period = static_cast<int>(std::round(2.0 * M_PI / wh));
  const int steps = 100 * per_period;
  const std::vector<double> E = energy_history(model, kKind, step_for(model, wh), steps);
  // The swing about the conserved modified energy is of relative size ~ w h / 2.
  for (double e : E) EXPECT_NEAR(e / E.front(), 1.0, wh);
  // And no drift: the last period's peak equals the first period's.
  EXPECT_NEAR(max_of(E, E.size() - per_period, E.size()), max_of(E, 0, per_period),
              1e-3 * E.front());
}

TEST(SymplecticEuler, CostsExactlyOneForceEvaluationPerStep) { expect_force_evals_per_step(kKind, 1); }

TEST(SymplecticEuler, IntegratesParticlesAndSpheresTogether) {
  expect_whole_state_integrated(kKind, +1.0);
}

TEST(SymplecticEuler, DivergesOnTheStiffSceneAtItsStep) { expect_diverges_early_on_the_stiff_scene(kKind); }

}  // namespace
}  // namespace clothsim::testing
