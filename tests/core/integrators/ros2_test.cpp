// ros2 (integrators/ros2.cpp) against its theory: order 2 on the damped and the undamped
// spring, whose axis is linear, so its step there is the stability function
//     R(z) = (1 + (1 - 2 gamma) z) / (1 - gamma z)^2,   gamma = 1 + 1/sqrt(2),
// at z = +-i w h: |R| < 1 at every w h > 0 (A-stable, damping) and -> 0 (L-stable); two
// force passes a step; the barrier refused.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::Ros2;

std::complex<double> ros2_factor(double wh) {
  const double gamma = 1.0 + 1.0 / std::sqrt(2.0);
  const std::complex<double> z(0.0, wh);
  return (1.0 + (1.0 - 2.0 * gamma) * z) / ((1.0 - gamma * z) * (1.0 - gamma * z));
}

TEST(Ros2, ConvergesAtSecondOrderOnTheDampedAndTheUndampedSpring) {
  for (const std::vector<std::string>& damping : {std::vector<std::string>{}, {"cloth.springs.structural.damping=0"}}) {
    const SceneDef scene = load_spring_scene(damping);
    const Oscillator o = oscillator_of(scene);
    const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
    for (double p : observed_orders(scene, kKind, h0, T)) EXPECT_NEAR(p, 2.0, 0.1) << "zeta " << o.zeta();
  }
}

TEST(Ros2, AmplifiesByItsStabilityFunctionBelowOneAndTendingToZero) {
  const Model model = undamped_spring_model();
  double last = 1.0;
  for (double wh : {0.01, 0.3, 1.0, 3.0, 30.0, 1000.0}) {
    const double h = step_for(model, wh);
    Eigen::Matrix2d m;  // on (e, h u): every column moves the spring by the same small length
    for (int col = 0; col < 2; ++col) {
      State s = initial_state(model);
      const Vec3 axis = (s.x.col(1) - s.x.col(0)).normalized();
      s.x.col(1) = s.x.col(0) + (model.springs.rest[0] + (col == 0 ? 1e-6 : 0.0)) * axis;
      s.v.col(1) = (col == 1 ? 1e-6 / h : 0.0) * axis;
      Workspace ws;
      const StepReport r = step(model, s, kKind, h, ws);
      ASSERT_TRUE(r.stats.converged);
      EXPECT_EQ(r.stats.force_evals, 2);
      m(0, col) = ((s.x.col(1) - s.x.col(0)).norm() - model.springs.rest[0]) / 1e-6;
      m(1, col) = h * (s.v.col(1) - s.v.col(0)).dot(axis) / 1e-6;
    }
    const std::complex<double> R = ros2_factor(wh);
    EXPECT_NEAR(m.determinant(), std::norm(R), 1e-7) << "w h " << wh;
    EXPECT_NEAR(m.trace(), 2.0 * R.real(), 1e-7) << "w h " << wh;
    EXPECT_LT(std::abs(R), 1.0);
    EXPECT_LT(std::abs(R), last + 1e-12) << "w h " << wh;  // falls with w h from 0.3 on
    if (wh >= 0.3) last = std::abs(R);
  }
  EXPECT_LT(last, 2e-3);
}

TEST(Ros2, RefusesTheBarrierForWantOfALineSearch) {
  EXPECT_NE(barrier_refusal(kKind).find("line search"), std::string::npos);
}

TEST(Ros2, IntegratesParticlesAndSpheresTogether) { expect_whole_state_integrated(kKind, 0.0, 1e-6); }

}  // namespace
}  // namespace clothsim::testing
