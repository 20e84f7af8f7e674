// Wrong is not ok: the rules that call a finite lane implausible, each on evidence made by hand.
#include "cli/frames/plausibility.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace clothsim;
using namespace clothsim::cli;

namespace {

// A 2 m x 2 m sheet (diagonal 2.83 m), nothing moving it but gravity.
const char* kSheet = R"(
name: sheet
dt: 1.0e-3
cloth: {particles: [5, 5], size: [2, 2], pinned: corners,
        springs: {structural: {stiffness: 20000, damping: 5}}}
)";

LaneEvidence healthy() {
  LaneEvidence e;
  e.totals.steps = 1000;
  e.totals.max_strain = 0.1;
  e.error_max = 0.01;
  return e;
}

}  // namespace

TEST(Plausibility, AHealthyLaneIsNotWrong) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  EXPECT_NEAR(cloth_size(model), std::sqrt(8.0), 1e-12);
  EXPECT_FALSE(external_work(model));
  EXPECT_FALSE(implausible(model, healthy()));
}

TEST(Plausibility, ALaneFarFromTheReferenceIsWrong) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  LaneEvidence e = healthy();
  e.error_max = 0.9 * kErrorFraction * cloth_size(model);
  EXPECT_FALSE(implausible(model, e));
  e.error_max = 1.1 * kErrorFraction * cloth_size(model);
  const auto verdict = implausible(model, e);
  ASSERT_TRUE(verdict);
  EXPECT_EQ(verdict->rfind("WRONG: ", 0), 0u) << *verdict;
  EXPECT_NE(verdict->find("from the reference"), std::string::npos) << *verdict;
}

TEST(Plausibility, ProjectionsOnMostStepsWithAStretchedClothAreWrong) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  LaneEvidence e = healthy();
  e.totals.projected_steps = 600;  // of 1000
  EXPECT_FALSE(implausible(model, e)) << "projections alone: the cloth may just rest on a collider";
  e.totals.max_strain = 2.0 * kStrainBound;
  ASSERT_TRUE(implausible(model, e));
  EXPECT_NE(implausible(model, e)->find("projected on 60% of steps"), std::string::npos);
  e.totals.projected_steps = 100;
  EXPECT_FALSE(implausible(model, e)) << "strain alone, projections on a tenth of the steps";
  e.totals.steps = kMinSteps - 1;
  e.totals.projected_steps = kMinSteps - 1;
  EXPECT_FALSE(implausible(model, e)) << "too few steps to judge";
}

TEST(Plausibility, EnergyGainedWithNoWorkDoneIsWrongUnlessASphereDrivesTheCloth) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  LaneEvidence e = healthy();
  e.energy_rise = 2.0 * kEnergyRise * model.energy_scale;
  ASSERT_TRUE(implausible(model, e));
  EXPECT_NE(implausible(model, e)->find("energy rose"), std::string::npos);
  const Model driven = clothsim::testing::model_from_yaml(std::string(kSheet) + R"(
spheres:
  - {center: [0, -1, 0], radius: 0.3, kinematic: true, motion: [{t: 0.1, velocity: [0, 1, 0]}]}
)");
  EXPECT_TRUE(external_work(driven));
  EXPECT_FALSE(implausible(driven, e)) << "a moving kinematic sphere does work on the cloth";
}
