// The pure planning of `compare`: per-run steps, sheet times, and the
// merged list of instants every run stops at.
#include "clip/common/plan_parts.h"

#include <gtest/gtest.h>

#include "clip/common/cli_common.h"
#include "cli/usage_error.h"
#include "scene/scene_parser.h"

using namespace clothsim;
using namespace clothsim::clip;
using clothsim::testing::usage_error;

namespace {

const std::vector<IntegratorKind> kFour = {IntegratorKind::ExplicitEuler, IntegratorKind::ImplicitEuler,
                                           IntegratorKind::Midpoint, IntegratorKind::Rk4};

}  // namespace

TEST(ParseDtList, DefaultsEveryRunToTheScenesStep) {
  EXPECT_EQ(parse_dt_list("", kFour, 1e-4), std::vector<double>(4, 1e-4));
}

TEST(ParseDtList, ABareStepAppliesToAllRuns) {
  EXPECT_EQ(parse_dt_list("2e-4", kFour, 1e-4), std::vector<double>(4, 2e-4));
}

TEST(ParseDtList, NamedStepsApplyToTheirRunsAndTheRestKeepTheDefault) {
  const auto dts = parse_dt_list("rk4=2e-4,implicit_euler=4e-3", kFour, 1e-4);
  EXPECT_EQ(dts, (std::vector<double>{1e-4, 4e-3, 1e-4, 2e-4}));
}

TEST(ParseDtList, ABareStepMixedWithNamedOnesIsTheDefaultForTheOthers) {
  // Order does not matter: a named step wins over the bare one either way.
  EXPECT_EQ(parse_dt_list("rk4=2e-4,5e-5", kFour, 1e-4), (std::vector<double>{5e-5, 5e-5, 5e-5, 2e-4}));
  EXPECT_EQ(parse_dt_list("5e-5,rk4=2e-4", kFour, 1e-4), (std::vector<double>{5e-5, 5e-5, 5e-5, 2e-4}));
}

TEST(ParseDtList, TakesAStepAsAFractionOfASecond) {
  // One step per frame is said as a fraction: 1/60 is the double 1.0 / 60, not a rounding of it.
  EXPECT_EQ(parse_dt_list("implicit_euler=1/60", kFour, 1e-4), (std::vector<double>{1e-4, 1.0 / 60, 1e-4, 1e-4}));
  EXPECT_EQ(parse_dt_list("1/240", kFour, 1e-4), std::vector<double>(4, 1.0 / 240));
  for (const char* bad : {"1/0", "1/", "/60", "1/60/2", "one/60"})
    EXPECT_NE(usage_error([bad] { parse_dt_list(std::string("rk4=") + bad, kFour, 1e-4); })
                  .find(std::string("'") + bad + "' is not a number"),
              std::string::npos)
        << bad;
}

TEST(ParseDtList, RejectsBadStepsAndNamesNotBeingCompared) {
  EXPECT_NE(usage_error([] { parse_dt_list("0", kFour, 1e-4); }).find("must be > 0"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_dt_list("rk4=fast", kFour, 1e-4); }).find("'fast' is not a number"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_dt_list("symplectic_euler=1e-3", kFour, 1e-4); })
                .find("not one of the integrators being compared"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_dt_list("rk4=1e-3,rk4=2e-3", kFour, 1e-4); }).find("given twice"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_dt_list("1e-3,2e-3", kFour, 1e-4); }).find("more than one"),
            std::string::npos);
}

TEST(ParseTimes, AcceptsIncreasingTimesWithinTheRun) {
  EXPECT_EQ(parse_times("0.5,1,2,4", 5.0), (std::vector<double>{0.5, 1, 2, 4}));
  EXPECT_EQ(parse_times("0,5", 5.0), (std::vector<double>{0, 5}));
}

TEST(ParseTimes, RejectsTimesOutsideTheRunOrOutOfOrder) {
  EXPECT_NE(usage_error([] { parse_times("1,6", 5.0); }).find("outside the run (0 to 5 s)"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_times("-1", 5.0); }).find("outside the run"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_times("2,1", 5.0); }).find("must increase"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_times("1,1", 5.0); }).find("must increase"), std::string::npos);
}

// Every target of a plan, walked as compare's threads walk it (tests only: compare never
// holds them all).
std::vector<Target> walk(const TargetPlan& plan) {
  std::vector<Target> out;
  TargetPlan::Cursor cursor(plan);
  for (Target t; cursor.next(t);) out.push_back(t);
  EXPECT_EQ(static_cast<long>(out.size()), plan.size());
  return out;
}

TEST(TargetPlan, HasOneFramePerStepOfOneOverFpsFromZeroToTheDuration) {
  const TargetPlan plan(5.0, 30.0, true, {});
  const auto targets = walk(plan);
  ASSERT_EQ(targets.size(), 151u);
  EXPECT_EQ(plan.frames(), 151);
  EXPECT_DOUBLE_EQ(targets.front().t, 0.0);
  EXPECT_DOUBLE_EQ(targets[45].t, 1.5);
  EXPECT_DOUBLE_EQ(targets.back().t, 5.0);
  for (std::size_t k = 0; k < targets.size(); ++k) EXPECT_EQ(targets[k].frame, static_cast<int>(k));
}

TEST(TargetPlan, MergesSheetTimesOntoFramesOrBetweenThem) {
  const TargetPlan plan(1.0, 10.0, true, {0.5, 0.55}, 0.25);
  const auto targets = walk(plan);
  EXPECT_EQ(plan.frames(), 11);
  ASSERT_EQ(targets.size(), 13u) << "0.55 and 0.25 fall between frames; 0.5 is frame 5";
  EXPECT_DOUBLE_EQ(targets[6].t, 0.5);
  EXPECT_EQ(targets[6].frame, 5);
  EXPECT_EQ(targets[6].column, 0);
  EXPECT_DOUBLE_EQ(targets[7].t, 0.55);
  EXPECT_EQ(targets[7].frame, -1);
  EXPECT_EQ(targets[7].column, 1);
  EXPECT_DOUBLE_EQ(targets[3].t, 0.25);
  EXPECT_TRUE(targets[3].still);
  for (std::size_t i = 1; i < targets.size(); ++i) EXPECT_LT(targets[i - 1].t, targets[i].t);
}

TEST(TargetPlan, ASheetTimeAndTheStillAtOneInstantAreOneTarget) {
  const auto targets = walk(TargetPlan(1.0, 10.0, true, {0.3, 0.95}, 0.3));
  ASSERT_EQ(targets.size(), 12u) << "0.3 is frame 3 (column and still); 0.95 between frames";
  EXPECT_EQ(targets[3].frame, 3);
  EXPECT_EQ(targets[3].column, 0);
  EXPECT_TRUE(targets[3].still);
  EXPECT_DOUBLE_EQ(targets[10].t, 0.95);
  EXPECT_EQ(targets[11].frame, 10);
}

TEST(TargetPlan, HoldsNoFrameListSoAHugeClipCostsNothingToPlan) {
  const TargetPlan plan(1e6, 30.0, true, {});  // 30 million frames
  EXPECT_EQ(plan.frames(), 30'000'001);
  TargetPlan::Cursor cursor(plan);
  Target t;
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(cursor.next(t));
  EXPECT_EQ(t.frame, 2);
  EXPECT_DOUBLE_EQ(t.t, 2.0 / 30.0);
}

TEST(TargetPlan, WithoutFramesStopsOnlyWhereSomethingIsWanted) {
  const auto sheet_only = walk(TargetPlan(5.0, 30.0, false, {0.5, 2.0}));
  ASSERT_EQ(sheet_only.size(), 2u);
  EXPECT_DOUBLE_EQ(sheet_only.back().t, 2.0);
  const auto summary_only = walk(TargetPlan(5.0, 30.0, false, {}));
  ASSERT_EQ(summary_only.size(), 1u);
  EXPECT_DOUBLE_EQ(summary_only.front().t, 5.0);
}

TEST(TimeLabel, ReadsAsATime) { EXPECT_EQ(time_label(0.5), "t = 0.5 s"); }

TEST(TargetPlan, AScaleWindowAddsTheFirstSecondsFrameTimesAsTargetsThatTakeNoPicture) {
  TargetPlan still(5.0, 10.0, false, {}, 2.0);
  still.with_scale_window(1.0);
  EXPECT_EQ(still.size(), 12) << "t = 0, 0.1 .. 1.0 and the still";
  TargetPlan::Cursor c(still);
  Target t;
  int shown = 0;
  double last = -1.0;
  while (c.next(t)) {
    EXPECT_GT(t.t, last);
    last = t.t;
    EXPECT_EQ(t.frame, -1);
    shown += t.still;
  }
  EXPECT_EQ(shown, 1);
  EXPECT_DOUBLE_EQ(last, 2.0);
  TargetPlan clip(5.0, 10.0, true, {});
  const long frames = clip.size();
  clip.with_scale_window(1.0);
  EXPECT_EQ(clip.size(), frames) << "a clip's frames are those instants already";
}

namespace {

SceneDef spring_scene() { return load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml", {}); }

}  // namespace

TEST(ParseVary, RefusesTheStepAndTheMethodPointingToTheLanesThatSayThem) {
  // --vary dt=1e-3,5e-4 ran both lanes at the scene's 1e-3 s, one labelled "dt = 5e-4".
  const SceneDef scene = spring_scene();
  const std::string dt = usage_error([&] { parse_vary("dt=1e-3,5e-4", scene); });
  EXPECT_EQ(dt.rfind("--vary dt: ", 0), 0u) << dt;
  EXPECT_NE(dt.find("--integrators symplectic_euler@1e-3,symplectic_euler@5e-4"), std::string::npos) << dt;
  // --vary integrator=explicit_euler,midpoint ran symplectic Euler twice under those names.
  for (const char* text : {"integrator=explicit_euler,midpoint", "integrator=rk4,midpoint"}) {
    const std::string m = usage_error([&] { parse_vary(text, scene); });
    EXPECT_EQ(m.rfind("--vary integrator: ", 0), 0u) << m;
    EXPECT_NE(m.find("give --integrators " + std::string(text).substr(11)), std::string::npos) << m;
  }
}

TEST(ParseVary, LabelsEveryValueApartWithAsManyFiguresAsItTakes) {
  const SceneDef scene = spring_scene();
  const Variation close = parse_vary("ks=100,100.0001", scene);
  EXPECT_EQ(close.label(0), "ks = 100");
  EXPECT_EQ(close.label(1), "ks = 100.0001");
  const Variation wide = parse_vary("ks=2e4,2.0001e4,2e5", scene);
  EXPECT_EQ(wide.label(0), "ks = 2e4");
  EXPECT_EQ(wide.label(1), "ks = 2.0001e4");
  const Variation usual = parse_vary("ks=2e3,2e4,2e5", scene);  // three figures as before
  EXPECT_EQ(usual.label(0), "ks = 2000");
  EXPECT_EQ(usual.label(2), "ks = 2e5");
  const Variation tiny = parse_vary("ks=1,1.0000000000000002", scene);  // one ulp apart still reads apart
  EXPECT_NE(tiny.label(0), tiny.label(1));
}

TEST(ParseVary, RefusesTheSameValueGivenTwice) {
  const SceneDef scene = spring_scene();
  const std::string same = usage_error([&] { parse_vary("ks=100,1e2", scene); });
  EXPECT_NE(same.find("gives the value 100 twice (items 1 and 2)"), std::string::npos) << same;
  EXPECT_NE(usage_error([&] { parse_vary("collision.model=barrier,projection,barrier", scene); })
                .find("gives the value barrier twice (items 1 and 3)"),
            std::string::npos);
}
