// The adaptive pairs (core/integrators/adaptive.h) held to their theory on the damped spring's
// closed form: as fixed-step methods each converges at its order; under error control the error
// follows the tolerance, the higher order is the cheaper one at a tight tolerance, every
// target and event is reached exactly, and the targets asked for do not change the steps.
#include "core/integrators/adaptive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "oscillator.h"

namespace clothsim::testing {
namespace {

const IntegratorKind kPairs[] = {IntegratorKind::Bs3, IntegratorKind::Dopri5, IntegratorKind::Rkf78};

// The phase-space error at T of `n` fixed steps of `kind` (step(), not Run, which would
// control the step).
double fixed_step_error(const SceneDef& scene, IntegratorKind kind, int n, double T) {
  const Model model = build_model(scene);
  State state = initial_state(model);
  Workspace ws;
  for (int i = 0; i < n; ++i) step(model, state, kind, T / n, ws);
  return phase_error(oscillator_of(scene), state);
}

// The error at T of a Run under error control at tolerance `tol` (rtol = atol).
struct Controlled {
  double error;
  RunTotals totals;
};
Controlled controlled_error(const SceneDef& scene, IntegratorKind kind, double tol, double T) {
  Model model = build_model(scene);
  model.adaptive = AdaptiveDef{tol, tol};
  Run run(model, kind, 1e-3);
  EXPECT_TRUE(run.advance_to(T)) << integrator_name(kind);
  EXPECT_EQ(run.state().t, T) << "a target is landed on exactly";
  return {phase_error(oscillator_of(scene), run.state()), run.totals()};
}

TEST(AdaptivePairs, AsFixedStepMethodsConvergeAtTheirOrders) {
  const SceneDef scene = load_spring_scene();
  const double T = 1.0;
  // Steps coarse enough that rkf78's eighth order stays above round-off over two halvings.
  const struct {
    IntegratorKind kind;
    double order;
    int n0;
  } cases[] = {{IntegratorKind::Bs3, 3, 400}, {IntegratorKind::Dopri5, 5, 200}, {IntegratorKind::Rkf78, 8, 12}};
  for (const auto& c : cases) {
    const double e0 = fixed_step_error(scene, c.kind, c.n0, T), e1 = fixed_step_error(scene, c.kind, 2 * c.n0, T),
                 e2 = fixed_step_error(scene, c.kind, 4 * c.n0, T);
    EXPECT_NEAR(std::log2(e0 / e1), c.order, 0.15) << integrator_name(c.kind);
    EXPECT_NEAR(std::log2(e1 / e2), c.order, 0.15) << integrator_name(c.kind);
    EXPECT_EQ(integrator_info(c.kind).order, c.order) << "the registry says so";
  }
}

TEST(AdaptivePairs, TheErrorFollowsTheTolerance) {
  const SceneDef scene = load_spring_scene();
  for (IntegratorKind kind : kPairs) {
    double previous = INFINITY;
    for (double tol : {1e-4, 1e-6, 1e-8, 1e-10}) {
      const Controlled c = controlled_error(scene, kind, tol, 1.0);
      EXPECT_LT(c.error, 100.0 * tol) << integrator_name(kind) << " at " << tol;
      EXPECT_LT(c.error, previous) << integrator_name(kind) << ": a tighter tolerance, a smaller error";
      previous = c.error;
    }
  }
}

TEST(AdaptivePairs, TheHigherOrderIsTheCheaperAtATightTolerance) {
  const SceneDef scene = load_spring_scene();
  const double tol = 1e-10;
  const std::int64_t bs3 = controlled_error(scene, IntegratorKind::Bs3, tol, 1.0).totals.force_evals,
                     dopri5 = controlled_error(scene, IntegratorKind::Dopri5, tol, 1.0).totals.force_evals,
                     rkf78 = controlled_error(scene, IntegratorKind::Rkf78, tol, 1.0).totals.force_evals;
  EXPECT_LT(dopri5, bs3);
  EXPECT_LT(rkf78, dopri5);
}

TEST(AdaptivePairs, CountEveryTrialAndLandOnEveryTarget) {
  const SceneDef scene = load_spring_scene();
  Model model = build_model(scene);
  model.adaptive = AdaptiveDef{1e-8, 1e-8};
  clothsim::Run run(model, IntegratorKind::Dopri5, 0.5);  // a first trial far too long: refused, then shrunk
  for (double t : {0.1, 0.2, 1.0 / 3.0, 0.5}) {
    ASSERT_TRUE(run.advance_to(t));
    EXPECT_EQ(run.state().t, t);
  }
  const RunTotals& r = run.totals();
  EXPECT_GT(r.rejected_steps, 0) << "the 0.5 s first trial";
  EXPECT_GE(r.force_evals, 6 * (r.steps + r.rejected_steps)) << "six stages a trial, FSAL's seventh reused";
  EXPECT_LE(r.force_evals, 7 * (r.steps + r.rejected_steps) + 1);
  EXPECT_GT(r.largest_step, r.smallest_step) << "its own steps, shortened at the targets";
  EXPECT_EQ(run.metrics().rejected_steps, r.rejected_steps);
  EXPECT_EQ(run.metrics().step_size, r.last_step);
}

// Dense output on a smooth scene: what is asked for does not change the steps taken. A run
// asked for 30 frames on the way takes the same steps as one asked for T alone and ends in the
// same state to the bit; each frame's state is a side step of the pair from the step that
// crossed it, near the closed form at that instant.
TEST(AdaptivePairs, FramesAskedForDoNotChangeTheStepsTaken) {
  const SceneDef scene = load_spring_scene();
  Model model = build_model(scene);
  for (IntegratorKind kind : kPairs) {
    model.adaptive = AdaptiveDef{1e-6, 1e-6};
    clothsim::Run once(model, kind, 1e-3), framed(model, kind, 1e-3);
    ASSERT_TRUE(once.advance_to(1.0));
    for (int f = 1; f <= 30; ++f) {
      ASSERT_TRUE(framed.advance_to(f / 30.0));
      EXPECT_EQ(framed.state().t, f / 30.0);
      EXPECT_LT(phase_error(oscillator_of(scene), framed.state()), 1e-4) << integrator_name(kind) << " frame " << f;
    }
    EXPECT_EQ(framed.totals().steps, once.totals().steps) << integrator_name(kind);
    EXPECT_EQ(framed.totals().rejected_steps, once.totals().rejected_steps);
    EXPECT_GT(framed.totals().force_evals, once.totals().force_evals) << "the side steps are counted";
    EXPECT_EQ(framed.state().x, once.state().x) << integrator_name(kind);
    EXPECT_EQ(framed.state().v, once.state().v);
  }
}

TEST(AdaptivePairs, StopExactlyAtATimelineEventAndRestartAfterIt) {
  // The spring's free end pinned at 0.25 s: the pair steps to that instant, the pin takes, and
  // nothing moves after it (a pin stops its particle there).
  SceneDef scene = load_spring_scene({"events=[{t: 0.25, pin: [[1, 0]]}]"});
  Model model = build_model(scene);
  clothsim::Run run(model, IntegratorKind::Rkf78, 1e-3);
  ASSERT_TRUE(run.advance_to(0.25));
  const Vec3 at_pin = run.state().x.col(1);
  ASSERT_TRUE(run.advance_to(0.5));
  EXPECT_EQ(run.state().t, 0.5);
  EXPECT_EQ(run.state().next_action, model.timeline.size()) << "the event was applied";
  EXPECT_LT((run.state().x.col(1) - at_pin).norm(), 1e-12) << "pinned where the event found it";
}

}  // namespace
}  // namespace clothsim::testing
