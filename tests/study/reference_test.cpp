// The adaptive reference (study/reference.h) on the damped oscillator of spring.yaml (m = 1 kg,
// k = 100 N/m, d = 2 N s/m, 0.1 m initial stretch, one end pinned), whose closed form is known:
// it meets it to its tolerance at every time asked (dense output, not only at its own steps),
// its estimated error bounds its true error, and events at known times are honoured exactly.
#include "study/reference.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

using testing::scene_path;

Model spring_model(const std::vector<std::string>& sets = {}) {
  return build_model(load_scene(scene_path("spring.yaml"), sets));
}

// u'' + 2 u' + 100 u = 0, u(0) = 0.1, u'(0) = 0: zeta w0 = 1, wd = sqrt(99).
double closed_form(double t) {
  const double wd = std::sqrt(99.0);
  return 0.1 * std::exp(-t) * (std::cos(wd * t) + std::sin(wd * t) / wd);
}

double stretch(const State& s) { return (s.x.col(1) - s.x.col(0)).norm() - 1.0; }

TEST(AdaptiveReference, MeetsTheDampedOscillatorsClosedFormToItsToleranceAtEveryFrameTime) {
  const Model model = spring_model();
  AdaptiveReference ref(model, 1e-9);
  double worst = 0.0;
  for (int frame = 1; frame <= 60; ++frame) {  // 1/30 s frames: between the solver's own steps
    const double t = frame / 30.0;
    ASSERT_TRUE(ref.advance_to(t));
    EXPECT_DOUBLE_EQ(ref.state().t, t);
    worst = std::max(worst, std::abs(stretch(ref.state()) - closed_form(t)));
  }
  EXPECT_LT(worst, 1e-9) << "the solve at 1e-9 is the one served";
  EXPECT_GE(ref.estimated_error(), worst) << "the estimate bounds the served solve's error";
  EXPECT_LE(ref.estimated_error(), 3.0 * worst) << "and is within 3x of it";
  EXPECT_GT(ref.totals().force_evals, 0);
}

// The estimate against the truth on a cloth: a 7x7 barrier drape (drape_smooth.yaml's ball,
// barrier and first push, t = 1 to 1.3 s) against a solve at 1e-12 standing for the true
// motion. At every frame the estimate so far (what a tile prints) is at least the served
// solve's largest error so far and at most 3x it (reference.h: twice the distance to a check
// 10x tighter lies within [1, 3]x when the check's error is under half the served one's).
TEST(AdaptiveReference, EstimatesItsServedErrorWithinOneToThreeTimesAtEveryFrameOfASmoothDrape) {
  const Model model = build_model(load_scene(scene_path("drape_smooth.yaml"), {"cloth.particles=[7,7]"}));
  AdaptiveReference ref(model);
  AdaptiveSolve truth(model, 1e-12);
  double true_error = 0.0;
  for (int frame = 1; frame <= 45; ++frame) {
    const double t = frame / 30.0;
    ASSERT_TRUE(ref.advance_to(t));
    ASSERT_TRUE(truth.advance_to(t));
    true_error = std::max(true_error, largest_particle_distance(model, ref.state(), truth.state()));
    ASSERT_GT(true_error, 0.0);
    const double ratio = ref.estimated_error() / true_error;
    EXPECT_GE(ratio, 1.0) << "at t = " << t << " s: estimate " << ref.estimated_error() << ", true " << true_error;
    EXPECT_LE(ratio, 3.0) << "at t = " << t << " s: estimate " << ref.estimated_error() << ", true " << true_error;
  }
  EXPECT_GT(true_error, 1e-11) << "the push makes an error well above the truth's own";
}

TEST(AdaptiveReference, ATighterToleranceGivesASmallerError) {
  const Model model = spring_model();
  double error[2];
  const double tolerances[2] = {1e-6, 1e-9};
  for (int i = 0; i < 2; ++i) {
    AdaptiveSolve solve(model, tolerances[i]);
    ASSERT_TRUE(solve.advance_to(1.0));
    error[i] = std::abs(stretch(solve.state()) - closed_form(1.0));
  }
  EXPECT_LT(error[1], 1e-2 * error[0]);
  EXPECT_LT(error[0], 1e-4);
}

TEST(AdaptiveReference, StopsExactlyAtAnEventAndRestartsFromIt) {
  // The free end is pinned at t = 0.3 s: from there it stays where it was, at rest.
  const Model model = spring_model({"events=[{t: 0.3, pin: [[1, 0]]}]"});
  AdaptiveSolve solve(model, 1e-10);
  ASSERT_TRUE(solve.advance_to(1.0));
  EXPECT_NEAR(stretch(solve.state()), closed_form(0.3), 1e-9);
  EXPECT_EQ(solve.state().v.col(1).norm(), 0.0);
}

TEST(AdaptiveReference, OnlyScenesWithoutProjectedContactsAreSmooth) {
  EXPECT_TRUE(smooth_scene(spring_model()));
  EXPECT_FALSE(smooth_scene(build_model(load_scene(scene_path("drape.yaml"), {}))));
  EXPECT_TRUE(smooth_scene(build_model(load_scene(scene_path("drape_smooth.yaml"), {}))));
  EXPECT_TRUE(smooth_scene(build_model(load_scene(scene_path("drape.yaml"), {"collision.model=barrier"}))));
}

}  // namespace
}  // namespace clothsim::analysis
