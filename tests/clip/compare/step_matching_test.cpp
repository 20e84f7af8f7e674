// compare --match: the steps chosen for cost and for error, and the option's grammar.
#include "clip/compare/step_matching.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>

#include "clip/common/cli_common.h"
#include "core/run/simulation.h"
#include "test_support.h"

using namespace clothsim;
using namespace clothsim::clip;

namespace {

// A 6 x 6 sheet pinned at its corners over 0.3 s.
const char* kSheet = R"(
name: sheet
dt: 1.0e-3
duration: 0.3
cloth: {particles: [6, 6], size: [1, 1], pinned: corners,
        springs: {structural: {stiffness: 2000, damping: 2}, shear: {stiffness: 2000, damping: 2}}}
render: {fps: 30}
)";

const MatchClip kClip{0.3, 30.0, 1e-3};

// The largest particle distance of `lane` at step h from RK4 at 1/(30 x 334) s (the searches'
// reference: 1e-4 s in whole steps a frame) over the clip's first 10 frames.
double worst_over_frames(const Model& model, const Lane& lane, double h) {
  clothsim::Run run(model, lane.kind, h, lane_settings(model, lane)), ref(model, IntegratorKind::Rk4, 1.0 / (30.0 * 334.0));
  double e = 0.0;
  for (int f = 0; f <= 9; ++f) {
    if (!run.advance_to(f / 30.0)) return std::numeric_limits<double>::infinity();
    ref.advance_to(f / 30.0);
    e = std::max(e, (run.state().x - ref.state().x).leftCols(model.num_particles).colwise().norm().maxCoeff());
  }
  return e;
}

}  // namespace

TEST(StepMatching, ParsesCostErrorAndNoneAndRefusesTheRest) {
  EXPECT_EQ(parse_match({"cost"}).kind, MatchKind::Cost);
  EXPECT_EQ(parse_match({"none"}).kind, MatchKind::None);
  const MatchRequest e = parse_match({"error", "1e-3"});
  EXPECT_EQ(e.kind, MatchKind::Error);
  EXPECT_EQ(e.tolerance, 1e-3);
  EXPECT_THROW(parse_match({"error"}), UsageError);
  EXPECT_THROW(parse_match({"error", "-1"}), UsageError);
  EXPECT_THROW(parse_match({"speed"}), UsageError);
}

// Free: the lanes given no step of their own, by @STEP or --dt (where the step came from is a
// field of the lane, set as it is parsed, not found by parsing again).
std::vector<bool> free_lanes(const std::string& integrators, const std::string& dt, double scene_dt) {
  std::vector<bool> free;
  for (const Lane& l : parse_lanes(integrators, dt, scene_dt)) free.push_back(l.free_step());
  return free;
}

TEST(StepMatching, OnlyLanesWithoutAStepOfTheirOwnAreFree) {
  EXPECT_EQ(free_lanes("rk4,midpoint@2e-4,explicit_euler", "", 1e-4), (std::vector<bool>{true, false, true}));
  EXPECT_EQ(free_lanes("rk4,midpoint", "rk4=1e-3", 1e-4), (std::vector<bool>{false, true}));
  EXPECT_EQ(free_lanes("course", "", 1e-4), (std::vector<bool>{true, true, true, true}));
  EXPECT_EQ(free_lanes("rk4", "1e-4", 1e-4), (std::vector<bool>{false})) << "--dt equal to the scene's is still given";
}

TEST(StepMatching, ExplicitLanesMatchTheCheapestByTheirEvaluationsPerStep) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  std::vector<Lane> lanes = parse_lanes("symplectic_euler,midpoint,rk4,rk4@2e-3", "", 1e-3);
  const auto how = match_steps(model, lanes, {MatchKind::Cost, 0.0}, kClip, lanes[0]);
  EXPECT_DOUBLE_EQ(lanes[0].dt, 1e-3);
  EXPECT_NEAR(lanes[1].dt, 2e-3, 1e-15);
  EXPECT_NEAR(lanes[2].dt, 4e-3, 1e-15);
  EXPECT_DOUBLE_EQ(lanes[3].dt, 2e-3) << "a lane with its own @STEP keeps it";
  EXPECT_EQ(lanes[0].step_from, StepFrom::Scene) << "the cheapest keeps the scene's step";
  EXPECT_EQ(lanes[2].step_from, StepFrom::MatchedCost);
  EXPECT_EQ(lanes[3].step_from, StepFrom::Written);
  EXPECT_NE(how[0].find("cheapest"), std::string::npos) << how[0];
  EXPECT_NE(how[2].find("matched on cost"), std::string::npos) << how[2];
  EXPECT_EQ(how[3], "your step");
}

TEST(StepMatching, AnImplicitLaneIsMatchedByPilotsToWithinTheirTolerance) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  std::vector<Lane> lanes = parse_lanes("symplectic_euler,implicit_euler", "", 1e-3);
  const auto how = match_steps(model, lanes, {MatchKind::Cost, 0.0}, kClip, lanes[0]);
  EXPECT_GT(lanes[1].dt, 1e-3) << "implicit Euler's steps cost more than one pass: it takes longer ones";
  // The pilots ran over the clip's first 0.3 s: at the step chosen that costs about what the
  // symplectic lane does (Newton's iteration counts jump with the step, so not to the search's
  // 5 % everywhere), far closer than at the scene's step.
  const double at_scene = pilot_cost(model, lanes[1], 1e-3, 0.3), chosen = pilot_cost(model, lanes[1], lanes[1].dt, 0.3);
  EXPECT_GT(at_scene / 1000.0, 2.0);
  EXPECT_NEAR(chosen / 1000.0, 1.0, 0.25) << how[1];
  EXPECT_EQ(lanes[1].step_text.rfind("1/", 0), 0u) << lanes[1].step_text;
}

TEST(StepMatching, ErrorMatchingTakesTheLargestStepWithinTheTolerance) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  std::vector<Lane> lanes = parse_lanes("symplectic_euler", "", 1e-3);
  const Lane reference = parse_reference("rk4@1e-4", lanes);
  const double tol = 1e-3;
  const auto how = match_steps(model, lanes, {MatchKind::Error, tol}, kClip, reference);
  ASSERT_NE(how[0].find("matched on error"), std::string::npos) << how[0];
  EXPECT_EQ(lanes[0].step_from, StepFrom::MatchedError);
  const long k = std::lround(1.0 / (30.0 * lanes[0].dt));
  ASSERT_GE(k, 1);
  // Within tolerance at that step, and not at the next larger one of the form 1 / (30 k).
  const auto worst = [&](double h) { return worst_over_frames(model, lanes[0], h); };
  EXPECT_LE(worst(lanes[0].dt), tol);
  if (k > 1) {
    EXPECT_GT(worst(1.0 / (30.0 * static_cast<double>(k - 1))), tol);
  }
}

// An adaptive pair given no tolerance is matched on it: under cost, its pilot at the matched
// tolerance costs about what the cheapest fixed-step lane does; a pair with its own :tol= keeps it.
TEST(StepMatching, AnAdaptiveLaneWithoutAToleranceIsMatchedOnItsToleranceForCost) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  std::vector<Lane> lanes = parse_lanes("midpoint,dopri5,bs3:tol=1e-5", "", 1e-3);
  const auto how = match_steps(model, lanes, {MatchKind::Cost, 0.0}, kClip, lanes[0]);
  ASSERT_GT(lanes[1].rtol, 0.0) << how[1];
  EXPECT_EQ(lanes[1].rtol, lanes[1].atol);
  EXPECT_NE(how[1].find("matched on cost"), std::string::npos) << how[1];
  const double target = 2.0 / 1e-3;  // midpoint at the scene's step: 2 passes a step
  EXPECT_NEAR(pilot_cost(model, lanes[1], lanes[1].dt, 0.3) / target, 1.0, 0.35) << how[1];
  EXPECT_EQ(lanes[2].rtol, 1e-5) << "a pair with its own tolerance keeps it";
  EXPECT_NE(how[2].find("its own steps"), std::string::npos) << how[2];
}

// Under error TOL, the loosest tolerance (to two figures) within TOL at every frame: it passes,
// and a tenfold looser one does not (the search's first trial is TOL itself).
TEST(StepMatching, AnAdaptiveLaneIsMatchedOnTheLoosestToleranceWithinTheError) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  std::vector<Lane> lanes = parse_lanes("dopri5", "", 1e-3);
  const Lane reference = parse_reference("rk4@1e-4", lanes);
  const double tol = 1e-6;
  const auto how = match_steps(model, lanes, {MatchKind::Error, tol}, kClip, reference);
  ASSERT_NE(how[0].find("matched on error"), std::string::npos) << how[0];
  const double chosen = lanes[0].rtol;
  ASSERT_GT(chosen, 0.0);  // a tolerance, relative and absolute, not metres: it may be looser than TOL
  const auto worst = [&](double t) {
    Lane l = lanes[0];
    l.rtol = l.atol = t;
    return worst_over_frames(model, l, 1e-3);
  };
  EXPECT_LE(worst(chosen), tol);
  EXPECT_GT(worst(10.0 * chosen), tol) << "a tenfold looser tolerance would have been taken";
}
