#include "study/study_run.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

Model spring(const std::vector<std::string>& sets = {}) {
  return build_model(load_scene(testing::scene_path("spring.yaml"), sets));
}

TEST(StudyRun, EndsExactlyAtTWhenTheStepDividesIt) {
  const StudyRun r = run_to(spring(), IntegratorKind::Rk4, 0.01, 1.0);
  EXPECT_TRUE(r.finished);
  EXPECT_EQ(r.totals.steps, 100);
  EXPECT_DOUBLE_EQ(r.final_state.t, 1.0);
  EXPECT_EQ(r.totals.force_evals, 400);
  EXPECT_GT(r.totals.cpu_seconds, 0.0);
}

TEST(StudyRun, PassesTByLessThanAStepWhenTheStepDoesNotDivideIt) {
  const StudyRun r = run_to(spring(), IntegratorKind::SymplecticEuler, 0.15, 1.0);  // w h = 1.5
  EXPECT_TRUE(r.finished);
  EXPECT_EQ(r.totals.steps, 7);
  EXPECT_NEAR(r.final_state.t, 1.05, 1e-12);
}

TEST(StudyRun, DivergedRunStopsThereAndSaysWhy) {
  const StudyRun r = run_to(spring({"cloth.springs.structural.damping=0"}), IntegratorKind::ExplicitEuler, 0.5, 100.0);
  EXPECT_FALSE(r.finished);
  EXPECT_FALSE(r.stopped);
  ASSERT_TRUE(r.divergence.has_value());
  EXPECT_LT(r.divergence->t, 100.0);
  EXPECT_LT(r.totals.steps, 200);
}

TEST(StudyRun, StopsBeforeTheNextStepWhenAsked) {
  int polls = 0;
  const StudyRun r = run_to(spring(), IntegratorKind::Rk4, 0.001, 10.0, [&] { return ++polls > 3; });
  EXPECT_TRUE(r.stopped);
  EXPECT_FALSE(r.finished);
  EXPECT_FALSE(r.divergence.has_value());
  EXPECT_EQ(r.totals.steps, 3);  // polled before each step: three steps, then the stop
}

}  // namespace
}  // namespace clothsim::analysis
