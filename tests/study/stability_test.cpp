// The stability search on spring.yaml made undamped (w = 10 rad/s), against linear theory
// for x'' = -w^2 x: symplectic Euler stable for w h < 2, RK4 for w h < 2.83, implicit
// Euler always, explicit Euler and midpoint never.
//
// Why T = 400 s and steps down to w h = 0.2: explicit Euler's and midpoint's growth is slow
// at small h (energy x exp(w^2 h t) and exp(w^4 h^3 t / 4)); to be called unstable their
// kinetic energy must pass 100 x the energy scale (1.5 J here, from 0.5 J: a factor 300,
// e^5.7). Over 400 s at w h = 0.2 midpoint grows by e^8 and explicit Euler by e^800, so both
// are caught at every step tried, yet the spring's 2 particles make each run milliseconds.
#include "study/stability.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "study/study_run.h"

namespace clothsim::analysis {
namespace {

using testing::scene_path;

constexpr double kOmega = 10.0;  // rad/s, sqrt(k / m)

Model undamped_spring(double stiffness = 100.0) {
  return build_model(load_scene(scene_path("spring.yaml"),
                                {"cloth.springs.structural.damping=0",
                                 "cloth.springs.structural.stiffness=" + std::to_string(stiffness)}));
}

StabilitySpec long_run(IntegratorKind kind) {
  StabilitySpec spec;
  spec.integrators = {kind};
  spec.duration = 400.0;
  spec.min_dt = 0.02;  // w h = 0.2
  spec.max_dt = 1.0;   // w h = 10
  spec.precision = 0.02;
  return spec;
}

TEST(Stability, FindsSymplecticEulersLimitAtOmegaHEqualsTwo) {
  const StabilityLimit l = largest_stable_dt(undamped_spring(), IntegratorKind::SymplecticEuler,
                                             long_run(IntegratorKind::SymplecticEuler));
  ASSERT_EQ(l.outcome, StabilityOutcome::Bracketed);
  EXPECT_NEAR(kOmega * l.stable_dt, 2.0, 0.03 * 2.0);
  EXPECT_LE(l.unstable_dt / l.stable_dt, 1.02 + 1e-12);
  EXPECT_LE(kOmega * l.stable_dt, 2.0);  // the bracket's stable end is below the limit
  EXPECT_FALSE(l.reason.empty());
}

TEST(Stability, TheFinestPrecisionEndsAndAFinerOneIsRefused) {
  StabilitySpec spec = long_run(IntegratorKind::SymplecticEuler);
  spec.duration = 40.0;
  spec.precision = 1e-12;
  const StabilityLimit l = largest_stable_dt(undamped_spring(), IntegratorKind::SymplecticEuler, spec);
  ASSERT_EQ(l.outcome, StabilityOutcome::Bracketed);
  EXPECT_LE(l.unstable_dt / l.stable_dt, 1.0 + 1e-12);
  EXPECT_LT(l.trials, 100);
  spec.precision = 1e-16;  // 1 + 1e-16 == 1: hi / lo could never pass it
  EXPECT_THROW(largest_stable_dt(undamped_spring(), IntegratorKind::SymplecticEuler, spec), StudyError);
}

TEST(Stability, FindsRk4sLimitAtOmegaHEqualsTwoPointEightThree) {
  const StabilityLimit l = largest_stable_dt(undamped_spring(), IntegratorKind::Rk4, long_run(IntegratorKind::Rk4));
  ASSERT_EQ(l.outcome, StabilityOutcome::Bracketed);
  EXPECT_NEAR(kOmega * l.stable_dt, 2.0 * std::sqrt(2.0), 0.03 * 2.83);
}

TEST(Stability, UnstableRunThatSettlesIntoABoundedWrongOrbitIsStillCaught) {
  // k = 25 N/m (w = 5): just past RK4's limit the spring's amplitude passes its rest length
  // and the particle collapses through its pin into a bounded orbit; with the engine's own
  // strain bound (10) that passed as stable at w h = 3.08. The study's bound (2) catches it.
  const StabilityLimit l = largest_stable_dt(undamped_spring(25.0), IntegratorKind::Rk4, long_run(IntegratorKind::Rk4));
  ASSERT_EQ(l.outcome, StabilityOutcome::Bracketed);
  EXPECT_NEAR(5.0 * l.stable_dt, 2.0 * std::sqrt(2.0), 0.03 * 2.83);
}

TEST(Stability, ImplicitEulerIsStableAtTheLargestStepTried) {
  const StabilityLimit l = largest_stable_dt(undamped_spring(), IntegratorKind::ImplicitEuler,
                                             long_run(IntegratorKind::ImplicitEuler));
  EXPECT_EQ(l.outcome, StabilityOutcome::StableAtMax);
  EXPECT_DOUBLE_EQ(l.stable_dt, 1.0);
  EXPECT_EQ(l.trials, 1);  // the cap is tried first: nothing invented above it
}

TEST(Stability, ImplicitEulerIsAlsoRunAtOneStepPerFrameAndReportedApart) {
  StabilitySpec spec = long_run(IntegratorKind::ImplicitEuler);
  spec.duration = 2.0;
  spec.max_dt = 0.1;
  spec.frame_dts = {1.0 / 60, 1.0 / 30};
  const StabilityLimit implicit = largest_stable_dt(undamped_spring(), IntegratorKind::ImplicitEuler, spec);
  EXPECT_EQ(implicit.trials, 3);  // the largest step, then the two frame steps
  ASSERT_EQ(implicit.frame_steps.size(), 2u);
  EXPECT_EQ(frame_step_text(implicit.frame_steps[0]), "1/60 s: ok, 120 steps converged");
  EXPECT_EQ(frame_step_text(implicit.frame_steps[1]), "1/30 s: ok, 60 steps converged");
  EXPECT_EQ(implicit.failure, Failure::None);
  spec.integrators = {IntegratorKind::Rk4};
  EXPECT_TRUE(largest_stable_dt(undamped_spring(), IntegratorKind::Rk4, spec).frame_steps.empty());
}

TEST(Stability, FrameStepTextSaysHowEachFrameStepEnded) {
  FrameStepResult r;
  r.dt = 1.0 / 30;
  r.steps = 6;
  r.unconverged_steps = 3;
  r.failure = Failure::NotConverged;
  EXPECT_EQ(frame_step_text(r), "1/30 s: 3 of 6 steps not converged");
  r.failure = Failure::Diverged;
  r.diverged_at = 0.1;
  EXPECT_EQ(frame_step_text(r), "1/30 s: diverged at t = 0.1 s");
  r.dt = 0.003;  // not one over a whole number: in seconds
  r.failure = Failure::None;
  EXPECT_EQ(frame_step_text(r), "0.003 s: ok, 6 steps converged");
}

TEST(Stability, TheFixedPointsFrameStepsSayItsIterationsNotThatTheyConverged) {
  // The course's "implicit" ends each step after K iterations with no tolerance: "converged"
  // would claim a solve it does not make. Run at one step per frame on the undamped spring
  // (w = 10 rad/s): 1/60 s is inside its w h <= 1, 1/5 s is not.
  Model model = undamped_spring();
  model.implicit.solver = ImplicitSolver::FixedPoint;
  model.implicit.fixed_point_iterations = 1;
  StabilitySpec spec = long_run(IntegratorKind::ImplicitEuler);
  spec.duration = 4.0;
  spec.max_dt = 0.1;
  spec.frame_dts = {1.0 / 60, 1.0 / 5};
  const StabilityLimit l = largest_stable_dt(model, IntegratorKind::ImplicitEuler, spec);
  ASSERT_EQ(l.frame_steps.size(), 2u);
  EXPECT_EQ(l.frame_steps[0].fixed_point_iterations, 1);
  EXPECT_EQ(frame_step_text(l.frame_steps[0]), "1/60 s: ok, 240 steps of 1 fixed-point iteration (no solve to converge)");
  EXPECT_EQ(l.frame_steps[1].failure, Failure::Diverged) << frame_step_text(l.frame_steps[1]);
  EXPECT_EQ(frame_step_text(l.frame_steps[1]).find("converged"), std::string::npos);
  FrameStepResult three = l.frame_steps[0];
  three.fixed_point_iterations = 3;
  EXPECT_EQ(frame_step_text(three), "1/60 s: ok, 240 steps of 3 fixed-point iterations (no solve to converge)");
  // Backward Euler's Newton solve on the same spring: its steps converged, and it says so.
  const StabilityLimit newton = largest_stable_dt(undamped_spring(), IntegratorKind::ImplicitEuler, spec);
  EXPECT_EQ(newton.frame_steps[0].fixed_point_iterations, 0);
  EXPECT_EQ(frame_step_text(newton.frame_steps[0]), "1/60 s: ok, 240 steps converged");
}

TEST(Stability, AnImplicitRunWhoseStepsMissedTheirToleranceIsNotStableAndSaysSo) {
  // Two Newton iterations on a swinging (rotating, so nonlinear) spring meet 1e-10 at steps
  // up to 0.02 s but not at 0.05 or 0.1 s (measured with `run`), where the run stays bounded
  // without having computed backward Euler's steps.
  const Model model = build_model(load_scene(
      scene_path("spring.yaml"), {"gravity=[0, -9.8, 0]", "implicit.newton_max_iterations=2",
                                  "implicit.newton_tolerance=1e-10"}));
  StabilitySpec spec = long_run(IntegratorKind::ImplicitEuler);
  spec.duration = 2.0;
  spec.max_dt = 0.1;
  spec.min_dt = 1e-3;
  const StabilityLimit l = largest_stable_dt(model, IntegratorKind::ImplicitEuler, spec);
  ASSERT_EQ(l.outcome, StabilityOutcome::Bracketed) << "reached T at 0.1 s, but unconverged";
  EXPECT_EQ(l.failure, Failure::NotConverged);
  EXPECT_NE(l.reason.find("steps not converged (largest final residual "), std::string::npos) << l.reason;
  EXPECT_GE(l.stable_dt, 0.02);
  EXPECT_LT(l.unstable_dt, 0.05 * 1.0001);
  const StudyRun at_limit = run_to(model, IntegratorKind::ImplicitEuler, l.stable_dt, spec.duration);
  EXPECT_TRUE(at_limit.finished);
  EXPECT_EQ(at_limit.totals.unconverged_steps, 0) << "the stable end converged at every step";
}

TEST(Stability, ADivergedRunFailsAsDiverged) {
  const StabilityLimit l = largest_stable_dt(undamped_spring(), IntegratorKind::SymplecticEuler,
                                             long_run(IntegratorKind::SymplecticEuler));
  EXPECT_EQ(l.failure, Failure::Diverged);
  EXPECT_EQ(l.reason.rfind("at t = ", 0), 0u) << l.reason;
}

TEST(Stability, ExplicitEulerAndMidpointAreNeverStableOverALongRun) {
  for (IntegratorKind kind : {IntegratorKind::ExplicitEuler, IntegratorKind::Midpoint}) {
    const StabilityLimit l = largest_stable_dt(undamped_spring(), kind, long_run(kind));
    EXPECT_EQ(l.outcome, StabilityOutcome::UnstableAtMin) << integrator_name(kind);
    EXPECT_DOUBLE_EQ(l.unstable_dt, 0.02);
    EXPECT_TRUE(std::isnan(l.stable_dt));
  }
}

TEST(Stability, SweepFindsTheLimitFallingAsOneOverTheSquareRootOfStiffness) {
  const Model soft = undamped_spring(100.0), stiff = undamped_spring(400.0);
  StabilitySpec spec = long_run(IntegratorKind::SymplecticEuler);
  spec.integrators = {IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitEuler};
  spec.jobs = 2;
  const std::vector<StabilityLimit> limits = stability_sweep({{100.0, &soft}, {400.0, &stiff}}, spec);
  ASSERT_EQ(limits.size(), 4u);
  EXPECT_EQ(limits[0].value, 100.0);
  EXPECT_EQ(limits[0].integrator, IntegratorKind::SymplecticEuler);
  EXPECT_EQ(limits[1].integrator, IntegratorKind::ImplicitEuler);
  EXPECT_EQ(limits[2].value, 400.0);
  EXPECT_NEAR(limits[0].stable_dt / limits[2].stable_dt, 2.0, 0.05);
  EXPECT_NEAR(limits[2].stable_dt, limits[2].estimate.dt_springs(), 0.03 * 0.1);  // 2 / w, w = 20
  EXPECT_EQ(limits[3].outcome, StabilityOutcome::StableAtMax);
}

TEST(Stability, RejectsARangeWithNothingInIt) {
  StabilitySpec spec = long_run(IntegratorKind::Rk4);
  spec.min_dt = 1.0;
  EXPECT_THROW(check(spec), StudyError);
  spec = long_run(IntegratorKind::Rk4);
  spec.integrators.clear();
  EXPECT_THROW(check(spec), StudyError);
}

TEST(Stability, StoppedSearchIsLeftOutOfTheSweep) {
  const Model model = undamped_spring();
  StudyHooks hooks;
  hooks.stop = [] { return true; };
  EXPECT_TRUE(stability_sweep({{100.0, &model}}, long_run(IntegratorKind::Rk4), hooks).empty());
}

// search_cost against the thread CPU the drape's searches took at 50 x 50, T = 0.2 s, the
// stability command's default range (docs/cluster.md, "What a search costs"): the
// estimate must order and scale them as measured, each ratio within a factor 2 (most within 1.3).
double drape_search_cost(IntegratorKind kind, double stiffness) {
  const Model model = build_model(load_scene(scene_path("drape.yaml"),
                                             {"cloth.particles=[50,50]", "cloth.springs.structural.stiffness=" +
                                                                             std::to_string(stiffness)}));
  StabilitySpec spec;
  spec.integrators = {kind};
  spec.duration = 0.2;
  spec.min_dt = 3.125e-6;
  spec.max_dt = 0.004;
  spec.frame_dts = {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30};
  return search_cost(model, kind, spec);
}

TEST(Stability, SearchCostScalesTheDrapesSearchesAsTheirMeasuredCpu) {
  using K = IntegratorKind;
  const double rk4_soft = drape_search_cost(K::Rk4, 2e4);  // measured 0.985 CPU s
  const auto near = [&](K kind, double stiffness, double measured_ratio) {
    const double ratio = drape_search_cost(kind, stiffness) / rk4_soft;
    EXPECT_GT(ratio, measured_ratio / 2.0) << integrator_name(kind) << " at " << stiffness;
    EXPECT_LT(ratio, measured_ratio * 2.0) << integrator_name(kind) << " at " << stiffness;
  };
  near(K::ExplicitEuler, 2e4, 0.254);     // 0.250 s
  near(K::ExplicitEuler, 2e7, 1.42);      // 1.403 s: its limit falls 6x at 2e7 N/m
  near(K::SymplecticEuler, 2e7, 0.220);   // 0.217 s
  near(K::Midpoint, 2e6, 0.466);          // 0.459 s
  near(K::Midpoint, 2e7, 0.780);          // 0.768 s
  near(K::ImplicitEuler, 2e4, 0.439);     // 0.432 s
  near(K::ImplicitEuler, 2e6, 1.35);      // 1.327 s
  near(K::ImplicitEuler, 2e7, 4.64);      // 4.573 s: the sweep's dearest search
  EXPECT_GT(drape_search_cost(K::ImplicitEuler, 2e7), 2.5 * drape_search_cost(K::ExplicitEuler, 2e7));
}

}  // namespace
}  // namespace clothsim::analysis
