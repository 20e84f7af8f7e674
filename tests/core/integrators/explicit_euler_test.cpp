// Forward Euler against its theory: first order; on the undamped spring its step is
// R(z) = 1 + z, z = i w h, so energy grows by |R|^2 = 1 + (w h)^2 every step, at every h.
#include <gtest/gtest.h>

#include <cmath>

#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::ExplicitEuler;

TEST(ExplicitEuler, ConvergesAtFirstOrderOnTheDampedSpring) {
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  ASSERT_GT(o.c, 0.0) << "spring.yaml is the damped oscillator";
  // w h from 0.01 down to 0.00125 over one second (1.6 periods): deep in the asymptotic range.
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.01);
  for (double p : observed_orders(scene, kKind, h0, T)) EXPECT_NEAR(p, 1.0, 0.15);
}

TEST(ExplicitEuler, GainsEnergyByOnePlusOmegaHSquaredPerStepAtEveryStepSize) {
  const Model model = undamped_spring_model();
  for (double wh : {0.01, 0.1, 0.5, 1.0}) {
    const double growth = 1.0 + wh * wh;
    // Enough steps to grow energy about eightfold: amplitude x2.8, still far from collapse.
    const int steps = static_cast<int>(std::ceil(std::log(8.0) / std::log(growth)));
    const std::vector<double> E = energy_history(model, kKind, step_for(model, wh), steps);
    for (std::size_t n = 1; n < E.size(); ++n) ASSERT_GT(E[n], E[n - 1]) << "w h = " << wh;
    EXPECT_NEAR(std::log(E.back() / E.front()) / steps, std::log(growth), 1e-9) << "w h = " << wh;
  }
}

TEST(ExplicitEuler, CostsExactlyOneForceEvaluationPerStep) { expect_force_evals_per_step(kKind, 1); }

TEST(ExplicitEuler, IntegratesParticlesAndSpheresTogether) {
  expect_whole_state_integrated(kKind, -1.0);
}

TEST(ExplicitEuler, DivergesOnTheStiffSceneAtItsStep) { expect_diverges_early_on_the_stiff_scene(kKind); }

}  // namespace
}  // namespace clothsim::testing
