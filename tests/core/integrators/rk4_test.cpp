// Classic RK4 against its theory: fourth order; on the undamped spring its step is the
// scaled rotation R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24, z = i w h, with
//     |R|^2 = 1 - (w h)^6 / 72 + (w h)^8 / 576,
// below 1 (slowly dissipative) for w h < 2 sqrt(2) ~ 2.83 and above 1 (divergent) beyond.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::Rk4;

double rk4_energy_factor(double wh) {
  return 1.0 - std::pow(wh, 6) / 72.0 + std::pow(wh, 8) / 576.0;
}

TEST(Rk4, ConvergesAtFourthOrderOnTheDampedSpring) {
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  // w h from 0.2 to 0.025: errors from ~1e-6 down to ~1e-10 of the amplitude, well above
  // round-off (~1e-14 over the 400 steps of the finest run).
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.2);
  for (double p : observed_orders(scene, kKind, h0, T)) EXPECT_NEAR(p, 4.0, 0.15);
}

TEST(Rk4, StaysBoundedBelowItsLimitAtOmegaHTwoPointSeven) {
  // |R|^2 = 0.52: energy decays, and 30 steps follow it over 8 orders of magnitude.
  const Model model = undamped_spring_model();
  const int steps = 30;
  const std::vector<double> E = energy_history(model, kKind, step_for(model, 2.7), steps);
  EXPECT_LT(rk4_energy_factor(2.7), 1.0);
  for (std::size_t n = 1; n < E.size(); ++n) ASSERT_LT(E[n], E[n - 1]);
  const double expected = std::log(rk4_energy_factor(2.7));
  EXPECT_NEAR(std::log(E.back() / E.front()) / steps, expected, 1e-6 * std::abs(expected));
}

TEST(Rk4, DivergesAboveItsLimitAtOmegaHTwoPointNineFive) {
  // |R| = 1.34 per step: 40 steps grow the amplitude ~1e5 times.
  const Model model = undamped_spring_model(1e-8);
  const int steps = 40;
  const std::vector<double> E = energy_history(model, kKind, step_for(model, 2.95), steps);
  EXPECT_GT(rk4_energy_factor(2.95), 1.0);
  EXPECT_GT(E.back(), 1e6 * E.front());
  const double expected = std::log(rk4_energy_factor(2.95));
  EXPECT_NEAR(std::log(E.back() / E.front()) / steps, expected, 1e-6 * expected);
}

TEST(Rk4, KeepsEnergyInASmallBandOverManyPeriods) {
  const Model model = undamped_spring_model();
  const double wh = 0.1;
  const int steps = 100 * static_cast<int>(std::round(2.0 * M_PI / wh));
  const std::vector<double> E = energy_history(model, kKind, step_for(model, wh), steps);
  // |R|^2 = 1 - 1.4e-8 per step: over 100 periods the energy drifts by under 1e-4.
  const auto [lo, hi] = std::minmax_element(E.begin(), E.end());
  EXPECT_GT(*lo, (1.0 - 1e-4) * E.front());
  EXPECT_LE(*hi, (1.0 + 1e-12) * E.front());
}

TEST(Rk4, CostsExactlyFourForceEvaluationsPerStep) { expect_force_evals_per_step(kKind, 4); }

TEST(Rk4, IntegratesParticlesAndSpheresTogether) {
  expect_whole_state_integrated(kKind, 0.0);
}

TEST(Rk4, DivergesOnTheStiffSceneAtItsStep) { expect_diverges_early_on_the_stiff_scene(kKind); }

}  // namespace
}  // namespace clothsim::testing
