// Backward Euler against its theory. Newton: first order, and on the undamped spring the
// scaled rotation 1 / (1 - z), z = i w h, so energy shrinks by 1 / (1 + (w h)^2) per step at
// every step size. Fixed point with K iterations: 1 + z + ... + z^{K+1}, so K = 1 (the
// course's "implicit") is unstable on the oscillator for w h > 1. And the solve itself: a
// converged step satisfies backward Euler's equations, a capped one says it did not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>

#include "forces.h"
#include "core/integrators/oscillator.h"
#include "core/integrators/whole_state.h"
#include "test_support.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::ImplicitEuler;

std::string stiff_scene_path() { return std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml"; }

// Per-step energy factor |R(i w h)|^2 of K fixed-point iterations, R = sum_{j <= K+1} z^j.
double fixed_point_energy_factor(int K, double wh) {
  std::complex<double> R = 0.0, zj = 1.0;
  for (int j = 0; j <= K + 1; ++j, zj *= std::complex<double>(0.0, wh)) R += zj;
  return std::norm(R);
}

// log(E_N / E_0) / N, the observed per-step energy factor's log.
double log_energy_rate(const std::vector<double>& E) {
  return std::log(E.back() / E.front()) / static_cast<double>(E.size() - 1);
}

TEST(ImplicitEuler, ConvergesAtFirstOrderOnTheDampedSpring) {
  const SceneDef scene = load_spring_scene();
  const Oscillator o = oscillator_of(scene);
  const double T = 1.0, h0 = T / std::round(T * o.fastest_rate() / 0.01);
  for (double p : observed_orders(scene, kKind, h0, T)) EXPECT_NEAR(p, 1.0, 0.15);
}

TEST(ImplicitEuler, LosesEnergyByOneOverOnePlusOmegaHSquaredPerStepAtEveryStepSize) {
  const Model model = undamped_spring_model();
  for (double wh : {0.1, 1.0, 10.0, 100.0}) {
    const double factor = 1.0 / (1.0 + wh * wh);
    // Follow the decay over six orders of magnitude (not into round-off).
    const int steps = static_cast<int>(std::ceil(std::log(1e-6) / std::log(factor)));
    const std::vector<double> E = energy_history(model, kKind, step_for(model, wh), steps);
    for (std::size_t n = 1; n < E.size(); ++n) ASSERT_LT(E[n], E[n - 1]) << "w h = " << wh;
    EXPECT_NEAR(log_energy_rate(E), std::log(factor), 1e-6 * std::abs(std::log(factor)))
        << "w h = " << wh;
  }
}

TEST(ImplicitEuler, IsStableAtOmegaHOneHundred) {
  const Model model = undamped_spring_model(0.1);
  State state = initial_state(model);
  Workspace ws;
  const double E0 = energy(model, state);
  for (int n = 0; n < 200; ++n) {
    const StepReport r = step(model, state, kKind, step_for(model, 100.0), ws);
    ASSERT_TRUE(r.stats.converged) << "step " << n << " residual " << r.stats.residual;
    ASSERT_LE(energy(model, state), E0);
  }
  EXPECT_LT(energy(model, state), 1e-12 * E0);
}

TEST(ImplicitEuler, OneNewtonIterationSolvesTheLinearSpringExactly) {
  // On a linear force Baraff & Witkin's linearised step is backward Euler itself: the first
  // iterate already meets the tolerance. (Five steps at w h = 3 shrink the amplitude 300
  // times, keeping it far above the rounding of positions of order 1 m.)
  const Model model = undamped_spring_model(0.1);
  State state = initial_state(model);
  Workspace ws;
  for (int n = 0; n < 5; ++n) {
    const StepStats s = step(model, state, kKind, step_for(model, 3.0), ws).stats;
    EXPECT_EQ(s.newton_iterations, 1);
    EXPECT_EQ(s.force_evals, 2);  // f(x_n, v_n) and the residual check
    EXPECT_TRUE(s.converged);
    EXPECT_LT(s.residual, 1e-9);
  }
}

// Steps to follow a per-step energy factor over about eight orders of magnitude, no more:
// from e0 = 1e-6 m the amplitude then stays within (1e-10, 1e-2) m, linear and resolved.
int steps_for_factor(double factor) {
  return std::max(3, std::min(60, static_cast<int>(std::log(1e8) / std::abs(std::log(factor)))));
}

TEST(ImplicitEuler, FixedPointWithOneIterationIsUnstableExactlyWhereOnePlusZPlusZSquaredIs) {
  const Model model =
      undamped_spring_model(1e-6, {"implicit.solver=fixed_point", "implicit.iterations=1"});
  for (double wh : {0.5, 0.9, 1.1, 1.5}) {
    const double factor = fixed_point_energy_factor(1, wh);  // 1 - (w h)^2 + (w h)^4
    ASSERT_EQ(factor > 1.0, wh > 1.0);
    const std::vector<double> E =
        energy_history(model, kKind, step_for(model, wh), steps_for_factor(factor));
    EXPECT_EQ(E.back() > E.front(), wh > 1.0) << "w h = " << wh;
    EXPECT_NEAR(log_energy_rate(E), std::log(factor), 1e-6 * std::abs(std::log(factor)))
        << "w h = " << wh;
  }
}

TEST(ImplicitEuler, FixedPointWithKIterationsAmplifiesByTheTruncatedGeometricSeries) {
  for (int K : {2, 3, 5}) {
    const Model model =
        undamped_spring_model(1e-6, {"implicit.solver=fixed_point",
                                     "implicit.iterations=" + std::to_string(K)});
    for (double wh : {0.5, 1.2}) {
      const double factor = fixed_point_energy_factor(K, wh);
      const std::vector<double> E =
          energy_history(model, kKind, step_for(model, wh), steps_for_factor(factor));
      EXPECT_NEAR(log_energy_rate(E), std::log(factor), 1e-6 * std::abs(std::log(factor)))
          << "K = " << K << ", w h = " << wh;
    }
  }
}

TEST(ImplicitEuler, FixedPointCostsOnePlusKForceEvaluations) {
  for (int K : {1, 4}) {
    const Model model = sheet_with_two_spheres(
        {"implicit.solver=fixed_point", "implicit.iterations=" + std::to_string(K)});
    State state = initial_state(model);
    Workspace ws;
    const StepStats s = step(model, state, kKind, 1e-4, ws).stats;
    EXPECT_EQ(s.force_evals, 1 + K);
    EXPECT_EQ(s.newton_iterations, K);
    EXPECT_EQ(s.cg_iterations, 0);
  }
}

// The stiff cloth lying on the ball: springs stretched and compressed, contacts, gravity.
State stiff_state_in_contact(const Model& model) {
  clothsim::Run run(model, kKind, model.dt);
  EXPECT_TRUE(run.advance_to(0.4));
  return run.state();
}

TEST(ImplicitEuler, AConvergedNewtonStepSatisfiesBackwardEulersEquations) {
  const Model model = build_model(load_scene(stiff_scene_path()));
  State state = stiff_state_in_contact(model);
  Workspace ws;
  Eigen::Matrix3Xd f, f0;
  const double h = model.dt;
  for (int n = 0; n < 5; ++n) {
    const State before = state;
    const StepStats s = implicit_euler_step(model, state, h, ws);
    ASSERT_TRUE(s.converged) << "residual " << s.residual;
    EXPECT_LE(s.residual, model.implicit.newton_tolerance);
    EXPECT_EQ(s.force_evals, 1 + s.newton_iterations);
    // x+ = x + h v+ ...
    EXPECT_LT((state.x - before.x - h * state.v).norm(), 1e-12 * state.x.norm());
    // ... and M (v+ - v) = h f(x+, v+), to the Newton tolerance relative to |h f(x, v)|.
    total_forces(model, state.x, state.v, state.inv_mass, f);
    total_forces(model, before.x, before.v, before.inv_mass, f0);
    double r2 = 0.0, p2 = 0.0;  // |M dv - h f(x+, v+)|^2 and |M dv|^2 over movable bodies
    for (int i = 0; i < model.num_bodies(); ++i) {
      if (state.inv_mass[i] == 0.0) continue;
      const Vec3 momentum = (state.v.col(i) - before.v.col(i)) / state.inv_mass[i];
      r2 += (momentum - h * f.col(i)).squaredNorm();
      p2 += momentum.squaredNorm();
    }
    const double scale = std::max(h * f0.norm(), std::sqrt(p2));
    EXPECT_LE(std::sqrt(r2), 1.001 * model.implicit.newton_tolerance * scale);
    resolve_collisions(model, state);  // as step() would, to stay in a physical state
  }
}

TEST(ImplicitEuler, SaysSoWhenNewtonHitsItsIterationCapAboveTolerance) {
  // One iteration (Baraff & Witkin's step) cannot solve the nonlinear contact state to 1e-12.
  const Model model = build_model(load_scene(
      stiff_scene_path(), {"implicit.newton_max_iterations=1", "implicit.newton_tolerance=1e-12"}));
  State state = stiff_state_in_contact(model);
  Workspace ws;
  const StepStats s = implicit_euler_step(model, state, model.dt, ws);
  EXPECT_FALSE(s.converged);
  EXPECT_GT(s.residual, 1e-12);
  EXPECT_EQ(s.newton_iterations, 1);
  EXPECT_EQ(s.force_evals, 2);
  EXPECT_GT(s.cg_iterations, 0);
}

TEST(ImplicitEuler, RunsTheStiffSceneToTheEndLosingEnergyEveryStepAndOutsideEveryCollider) {
  // At the scene's 2 ms the explicit methods diverge within a few steps (their tests).
  // Backward Euler must not: every step loses energy, all of them converge, and after the
  // collision pass no particle is left inside the ball or under the ground. The loop is
  // step()'s phases written out, to measure the energy between the integrator and the
  // collisions: the contact projection moves particles without regard to their springs and
  // can add energy at a large step, which is not the integrator's doing.
  const Model model = build_model(load_scene(stiff_scene_path()));
  ASSERT_TRUE(model.has_ground);
  ASSERT_EQ(model.num_spheres, 1);
  const Vec3 c = model.initial_x.col(model.sphere_body(0));
  const double r = model.sphere_radius[0], h = model.dt;
  State state = initial_state(model);
  Workspace ws;
  const double E_start = energy(model, state);
  const auto steps = static_cast<std::int64_t>(std::llround(model.duration / h));
  int contacts = 0;
  for (std::int64_t n = 0; n < steps; ++n) {
    const double before = energy(model, state);
    const StepStats s = integrate(kKind, model, state, h, ws);
    ASSERT_TRUE(s.converged) << "step " << n << ": residual " << s.residual;
    ASSERT_LE(energy(model, state), before) << "step " << n;
    contacts += resolve_collisions(model, state).total();
    state.step += 1;
    state.t = static_cast<double>(state.step) * h;
    apply_due_actions(model, state);
    ASSERT_TRUE(state.x.allFinite());
    for (int p = 0; p < model.num_particles; ++p) {
      ASSERT_GE((state.x.col(p) - c).norm(), r) << "particle " << p << " in the ball, step " << n;
      ASSERT_GE(state.x(1, p), model.ground.height) << "particle " << p << " under the ground";
    }
  }
  EXPECT_NEAR(state.t, model.duration, 1e-9);
  EXPECT_GT(contacts, 0) << "the cloth is meant to land on the ball";
  EXPECT_LT(energy(model, state), 0.7 * E_start);
}

TEST(ImplicitEuler, SolvesAHardCompressedSheetAtAHugeStep) {
  // Every spring at 60% of its rest length, h = 0.5 s (w h ~ 100): the exact stiffness makes
  // the Newton matrix indefinite here (sparse_system_test), so this exercises the clamped
  // fallback. Backward Euler must still be solved, and the sheet must spring back, losing
  // energy, not blow up.
  const Model model = model_from_yaml(R"(
name: crumpled
gravity: [0, 0, 0]
cloth:
  particles: [5, 5]
  size: [1, 1]
  particle_mass: 0.1
  pinned: none
  springs:
    structural: {stiffness: 2000, damping: 1}
    shear: {stiffness: 2000, damping: 1}
    bend: {stiffness: 500, damping: 1}
implicit: {newton_max_iterations: 100}
)");
  State state = initial_state(model);
  std::srand(11);
  state.x = 0.6 * state.x + 1e-3 * Eigen::Matrix3Xd::Random(3, model.num_bodies());
  Workspace ws;
  double E = energy(model, state);
  for (int n = 0; n < 5; ++n) {
    const StepStats s = implicit_euler_step(model, state, 0.5, ws);
    ASSERT_TRUE(s.converged) << "step " << n << ": residual " << s.residual;
    ASSERT_TRUE(state.x.allFinite());
    EXPECT_LT(energy(model, state), E);
    E = energy(model, state);
  }
}

TEST(ImplicitEuler, CostsOneForceEvaluationPlusOnePerNewtonIteration) {
  const Model model = sheet_with_two_spheres();
  State state = initial_state(model);
  Workspace ws;
  for (int i = 0; i < 3; ++i) {
    const StepStats s = step(model, state, kKind, 1e-3, ws).stats;
    EXPECT_GE(s.newton_iterations, 1);
    EXPECT_EQ(s.force_evals, 1 + s.newton_iterations);
  }
  EXPECT_EQ(nominal_force_evals(kKind), 0);  // depends on the solve: reported per step
}

TEST(ImplicitEuler, IntegratesParticlesAndSpheresTogether) {
  expect_whole_state_integrated(kKind, +1.0, 1e-6);
}

}  // namespace
}  // namespace clothsim::testing
