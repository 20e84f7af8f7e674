// Explicit midpoint (RK2) against its theory: second order; on the undamped spring its step
// is R(z) = 1 + z + z^2/2, z = i w h, a scaled rotation with |R|^2 = 1 + (w h)^4 / 4 > 1:
// it gains energy at every step size, slowly when w h is small.
#include <gtest/gtest.h>

#include <cmath>

#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::Midpoint;

TEST(Midpoint, ConvergesAtSecondOrderOnTheDampedSpring) {
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
  for (double p : observed_orders(scene, kKind, h0, T)) EXPECT_NEAR(p, 2.0, 0.15);
}

TEST(Midpoint, GainsEnergyByOnePlusQuarterOmegaHToTheFourthPerStepAtEveryStepSize) {
  const Model model = undamped_spring_model();
  for (double wh : {0.05, 0.2, 0.5, 1.0}) {
    const double growth = 1.0 + std::pow(wh, 4) / 4.0;
    const int steps = std::min(200000, static_cast<int>(std::ceil(std::log(8.0) / std::log(growth))));
    const std::vector<double> E = energy_history(model, kKind, step_for(model, wh), steps);
    for (std::size_t n = 1; n < E.size(); ++n) ASSERT_GT(E[n], E[n - 1]) << "w h = " << wh;
    EXPECT_NEAR(std::log(E.back() / E.front()) / steps, std::log(growth), 1e-3 * std::log(growth))
        << "w h = " << wh;
  }
}

TEST(Midpoint, CostsExactlyTwoForceEvaluationsPerStep) { expect_force_evals_per_step(kKind, 2); }

TEST(Midpoint, IntegratesParticlesAndSpheresTogether) {
  expect_whole_state_integrated(kKind, 0.0);
}

TEST(Midpoint, DivergesOnTheStiffSceneAtItsStep) { expect_diverges_early_on_the_stiff_scene(kKind); }

}  // namespace
}  // namespace clothsim::testing
