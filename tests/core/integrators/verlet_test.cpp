// velocity_verlet and yoshida4 (integrators/verlet.h) against their theory: orders 2 and 4 on
// the undamped spring, where their step matrices have determinant 1 (energy bounded) below
// w h = 2 and 1.5734; one force pass a step carried in State::history, and only while the
// state is the one the last step left; the step matrices the registry's limits are read
// from are the steps the code takes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/integrators/oscillator.h"
#include "core/integrators/verlet.h"
#include "core/integrators/whole_state.h"
#include "core/model/stiffness_estimate.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kVerlet = IntegratorKind::VelocityVerlet;
constexpr IntegratorKind kYoshida = IntegratorKind::Yoshida4;

double max_of(const std::vector<double>& E, std::size_t from, std::size_t to) {
  return *std::max_element(E.begin() + from, E.begin() + to);
}

SceneDef undamped_spring_scene() { return load_spring_scene({"cloth.springs.structural.damping=0"}); }

TEST(VelocityVerlet, ConvergesAtSecondOrderOnTheUndampedSpring) {
  const SceneDef scene = undamped_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
  for (double p : observed_orders(scene, kVerlet, h0, T)) EXPECT_NEAR(p, 2.0, 0.05);
}

TEST(VelocityVerlet, KeepsSecondOrderWithTheDampersThroughItsPredictedVelocity) {
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  ASSERT_GT(o.zeta(), 0.0);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
  for (double p : observed_orders(scene, kVerlet, h0, T)) EXPECT_NEAR(p, 2.0, 0.1);
}

TEST(Yoshida4, ConvergesAtFourthOrderOnTheUndampedSpring) {
  const SceneDef scene = undamped_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.2);
  for (double p : observed_orders(scene, kYoshida, h0, T)) EXPECT_NEAR(p, 4.0, 0.1);
}

TEST(Yoshida4, FallsToSecondOrderWhereDampersBreakVerletsSymmetry) {
  // The predicted velocity makes the damped kick O(h^3) off a symmetric one, so the triple
  // jump's h^3 terms no longer cancel (verlet.h): order 2, and on this spring (zeta = 0.1)
  // an error larger than Verlet's at the same step, for three times its force passes.
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.05);
  for (double p : observed_orders(scene, kYoshida, h0, T)) EXPECT_NEAR(p, 2.0, 0.15);
  EXPECT_GT(error_at(scene, kYoshida, h0, T), error_at(scene, kVerlet, h0, T));
}

TEST(VelocityVerlet, StaysBoundedJustBelowTwoOverOmega) {
  const Model model = undamped_spring_model();
  const int steps = 4000;
  const std::vector<double> E = energy_history(model, kVerlet, step_for(model, 1.9), steps);
  EXPECT_LE(max_of(E, steps / 2, E.size()), 1.02 * max_of(E, 0, steps / 2));
  EXPECT_LT(max_of(E, 0, E.size()), 100.0 * E.front());
}

TEST(VelocityVerlet, DivergesJustAboveTwoOverOmega) {
  const Model model = undamped_spring_model(1e-8);
  const std::vector<double> E = energy_history(model, kVerlet, step_for(model, 2.1), 20);
  EXPECT_GT(E.back(), 1e8 * E.front());
}

TEST(Yoshida4, StaysBoundedBelowItsLimitAndDivergesAbove) {
  const double limit = analysis::step_matrix_limit(yoshida4_matrix, 1.0, 0.0);
  EXPECT_NEAR(limit, 1.5734, 1e-3);  // the triple jump's known bound, w h < 1.5734
  const Model model = undamped_spring_model(1e-8);
  const int steps = 4000;
  const std::vector<double> below = energy_history(model, kYoshida, step_for(model, 0.97 * limit), steps);
  EXPECT_LE(max_of(below, steps / 2, below.size()), 1.02 * max_of(below, 0, steps / 2));
  const std::vector<double> above = energy_history(model, kYoshida, step_for(model, 1.1 * limit), 200);
  EXPECT_GT(above.back(), 1e6 * above.front());
}

TEST(VelocityVerlet, KeepsEnergyInASmallBandOverManyPeriods) {
  const Model model = undamped_spring_model();
  const double wh = 0.05;
  const int per_period = static_cast<int>(std::round(2.0 * M_PI / wh));
  const std::vector<double> E = energy_history(model, kVerlet, step_for(model, wh), 100 * per_period);
  // Verlet's modified energy differs from the true one by O((w h)^2), not symplectic
  // Euler's O(w h).
  for (double e : E) EXPECT_NEAR(e / E.front(), 1.0, wh * wh);
  EXPECT_NEAR(max_of(E, E.size() - per_period, E.size()), max_of(E, 0, per_period), 1e-4 * E.front());
}

TEST(VerletStepMatrix, IsTheStepTheCodeTakesOnTheDampedSpring) {
  // Along its axis the spring is e'' = -w^2 e - (c/m) e': two steps from (e0, 0) and from
  // (0, u0) are the matrix applied twice to (e, u, a(e, u)), the second step's first kick
  // reusing the first's carried pass.
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const Model model = build_model(scene);
  const double h = 0.3 / o.omega(), w = o.omega(), c = o.c / o.m;
  for (const IntegratorKind kind : {kVerlet, kYoshida}) {
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> m;
    (kind == kVerlet ? velocity_verlet_matrix : yoshida4_matrix)(h, w, c, m.data());
    for (int col = 0; col < 2; ++col) {
      State s = initial_state(model);
      const Vec3 axis = (s.x.col(1) - s.x.col(0)).normalized();
      Eigen::Vector3d y(extension(o, s), 0.0, 0.0);
      if (col == 1) {
        s.x.col(1) = s.x.col(0) + o.rest * axis;  // at rest length, moving outwards at 1 m/s
        s.v.col(1) = axis;
        y = {0.0, 1.0, 0.0};
      }
      y[2] = -w * w * y[0] - c * y[1];
      Workspace ws;
      for (int n = 0; n < 2; ++n) {
        step(model, s, kind, h, ws);
        y = m * y;
        EXPECT_NEAR(extension(o, s), y[0], 1e-12) << integrator_name(kind) << " column " << col << " step " << n;
        EXPECT_NEAR(extension_rate(s), y[1], 1e-12) << integrator_name(kind) << " column " << col << " step " << n;
      }
    }
  }
}

TEST(VerletLimits, AreTwoOverOmegaUndampedAndShrinkWithTheDampers) {
  EXPECT_NEAR(analysis::step_matrix_limit(velocity_verlet_matrix, 1.0, 0.0), 2.0, 1e-6);
  EXPECT_LT(analysis::step_matrix_limit(velocity_verlet_matrix, 1.0, 0.5), 2.0);
  EXPECT_NEAR(integrator_info(kVerlet).linear_limit(1.0, 0.0, {}), 2.0, 1e-6);
}

TEST(VelocityVerlet, CostsOneForcePassAStepAfterTheFirst) {
  const Model model = sheet_with_two_spheres();
  State state = initial_state(model);
  Workspace ws;
  EXPECT_EQ(step(model, state, kVerlet, 1e-4, ws).stats.force_evals, 2);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(step(model, state, kVerlet, 1e-4, ws).stats.force_evals, 1);
  EXPECT_EQ(nominal_force_evals(kVerlet), 1);
  State y = initial_state(model);
  EXPECT_EQ(step(model, y, kYoshida, 1e-4, ws).stats.force_evals, 4);
  EXPECT_EQ(step(model, y, kYoshida, 1e-4, ws).stats.force_evals, 3);
  EXPECT_EQ(nominal_force_evals(kYoshida), 3);
}

TEST(VelocityVerlet, StartsAfreshWhenTheStateIsChangedBetweenSteps) {
  // A write from outside (a projection contact, an event, Python's positions) makes the
  // carried pass stale: the next step evaluates again, and matches a run that never had it.
  const Model model = sheet_with_two_spheres();
  State state = initial_state(model);
  Workspace ws;
  step(model, state, kVerlet, 1e-4, ws);
  state.v.col(5) += Vec3(0.0, 0.1, 0.0);
  State fresh = state;
  fresh.history = {};
  EXPECT_EQ(step(model, state, kVerlet, 1e-4, ws).stats.force_evals, 2);
  step(model, fresh, kVerlet, 1e-4, ws);
  EXPECT_EQ(state.x, fresh.x);
  EXPECT_EQ(state.v, fresh.v);
}

TEST(VelocityVerlet, ACopiedStateContinuesBitForBit) {
  const Model model = sheet_with_two_spheres();
  State a = initial_state(model);
  Workspace ws, ws2;
  for (int i = 0; i < 5; ++i) step(model, a, kYoshida, 1e-4, ws);
  State b = a;
  for (int i = 0; i < 5; ++i) step(model, a, kYoshida, 1e-4, ws), step(model, b, kYoshida, 1e-4, ws2);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.v, b.v);
}

TEST(VelocityVerlet, IntegratesParticlesAndSpheresTogether) { expect_whole_state_integrated(kVerlet, 0.0); }
TEST(Yoshida4, IntegratesParticlesAndSpheresTogether) { expect_whole_state_integrated(kYoshida, 0.0); }

TEST(VelocityVerlet, DivergesOnTheStiffSceneAtItsStep) { expect_diverges_early_on_the_stiff_scene(kVerlet); }
TEST(Yoshida4, DivergesOnTheStiffSceneAtItsStep) { expect_diverges_early_on_the_stiff_scene(kYoshida); }

}  // namespace
}  // namespace clothsim::testing
