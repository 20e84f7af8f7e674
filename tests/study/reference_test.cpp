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
  EXPECT_LT(worst, 1e-10) << "the tighter solve (1e-11) is the one served";
  EXPECT_GT(ref.estimated_error(), worst) << "the estimate bounds the served solve's error";
  EXPECT_LT(ref.estimated_error(), 1e-8);
  EXPECT_GT(ref.totals().force_evals, 0);
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
