// Wrong is not ok: the rules that call a finite lane implausible, each on evidence made by hand.
#include "clip/frames/plausibility.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace clothsim;
using namespace clothsim::clip;

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

TEST(Plausibility, TheRunsOwnWrongVerdictIsTheLanesAndComesFirst) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  LaneEvidence e = healthy();
  e.totals.wrong = Divergence{10, 0.01, "energy rose 5 J with no work done"};
  e.error_max = 1.1 * kErrorFraction * cloth_size(model);
  const auto verdict = implausible(model, e);
  ASSERT_TRUE(verdict);
  EXPECT_EQ(*verdict, "WRONG: energy rose 5 J with no work done");
}
