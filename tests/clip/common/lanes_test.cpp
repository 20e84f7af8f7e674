// Lanes: NAME[@STEP] items, course, --dt for the lanes without a step, the reference.
#include "clip/common/lanes.h"

#include <gtest/gtest.h>

#include <memory>

#include "cli/usage_error.h"
#include "core/run/simulation.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

using namespace clothsim;
using namespace clothsim::clip;
using clothsim::testing::usage_error;

TEST(ParseLanes, OneIntegratorAtSeveralStepsAndFractions) {
  const auto lanes = parse_lanes("rk4@1e-4, rk4@4e-4,implicit_euler@1/60", "", 1e-3);
  ASSERT_EQ(lanes.size(), 3u);
  EXPECT_EQ(lanes[0].kind, IntegratorKind::Rk4);
  EXPECT_EQ(lanes[0].dt, 1e-4);
  EXPECT_EQ(lanes[1].dt, 4e-4);
  EXPECT_EQ(lanes[2].kind, IntegratorKind::ImplicitEuler);
  EXPECT_EQ(lanes[2].dt, 1.0 / 60);
  EXPECT_EQ(lanes[2].label(), "implicit_euler  dt = 1/60 s") << "the step as written";
  EXPECT_EQ(lane_directories(lanes), (std::vector<std::string>{"rk4@1e-4", "rk4@4e-4", "implicit_euler"}));
}

TEST(ParseLanes, StepsWithoutAtComeFromDtOrTheScene) {
  const auto scene = parse_lanes("rk4,midpoint@2e-4", "", 1e-3);
  EXPECT_EQ(scene[0].dt, 1e-3);
  EXPECT_EQ(scene[0].label(), "rk4  dt = 0.001 s");
  const auto all = parse_lanes("rk4,midpoint@2e-4,explicit_euler", "5e-4", 1e-3);
  EXPECT_EQ(all[0].dt, 5e-4);
  EXPECT_EQ(all[1].dt, 2e-4) << "@STEP wins";
  EXPECT_EQ(all[2].dt, 5e-4);
  const auto named = parse_lanes("rk4,rk4@1e-5,midpoint", "rk4=1/240", 1e-3);
  EXPECT_EQ(named[0].dt, 1.0 / 240);
  EXPECT_EQ(named[1].dt, 1e-5);
  EXPECT_EQ(named[2].dt, 1e-3);
  // --dt 1/240 is shown as the fraction it was given in, as @1/240 is (not "0.00416667").
  EXPECT_EQ(named[0].label(), "rk4  dt = 1/240 s");
  EXPECT_EQ(lane_directories(named), (std::vector<std::string>{"rk4@1_240", "rk4@1e-5", "midpoint"}));
  EXPECT_EQ(step_string(1.0 / 30.0), "1/30");
  EXPECT_EQ(step_string(1e-4), "0.0001") << "a decimal %g prints exactly stays one";
  EXPECT_EQ(step_string(0.0333333), "0.0333333") << "not quite 1/30";
  EXPECT_EQ(step_string(0.033333333333333), "0.0333333") << "within 1e-14 of 1/30, still not it";
}

TEST(ParseLanes, CourseIsTheCoursesFourWithItsFixedPointImplicit) {
  const auto lanes = parse_lanes("course", "", 1e-4);
  ASSERT_EQ(lanes.size(), 4u);
  EXPECT_EQ(lanes[0].kind, IntegratorKind::ExplicitEuler);
  EXPECT_EQ(lanes[1].kind, IntegratorKind::ImplicitEuler);
  EXPECT_TRUE(lanes[1].fixed_point);
  EXPECT_EQ(lanes[1].name(), "implicit_euler (fixed point)");
  EXPECT_EQ(lanes[2].kind, IntegratorKind::Midpoint);
  EXPECT_EQ(lanes[3].kind, IntegratorKind::Rk4);
  for (const Lane& l : lanes) EXPECT_EQ(l.dt, 1e-4);
  // Beside a Newton implicit_euler lane at the same step: two different lanes.
  EXPECT_EQ(parse_lanes("course,implicit_euler", "", 1e-4).size(), 5u);
}

TEST(ParseLanes, EveryLaneIsSpeltAsIntegratorsTakesItBack) {
  // --summary's "lane" and the narrow tiles' labels: pasted into --integrators, the same lanes.
  for (const char* list : {"course", "rk4@1e-4,rk4@4e-4,implicit_euler@1/60", "course,implicit_euler,symplectic_euler@2e-4"}) {
    const auto lanes = parse_lanes(list, "", 1e-4);
    std::string spelt;
    for (const Lane& l : lanes) spelt += (spelt.empty() ? "" : ",") + l.spelling();
    const auto again = parse_lanes(spelt, "", 1.0);  // every step given: the scene's dt unused
    ASSERT_EQ(again.size(), lanes.size()) << spelt;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      EXPECT_EQ(again[i].kind, lanes[i].kind) << spelt;
      EXPECT_EQ(again[i].dt, lanes[i].dt) << spelt;
      EXPECT_EQ(again[i].fixed_point, lanes[i].fixed_point) << spelt;
      EXPECT_EQ(again[i].spelling(), lanes[i].spelling());
    }
  }
  const Lane fixed = parse_lanes("course", "", 1e-4)[1];
  EXPECT_EQ(fixed.spelling(), "implicit_euler_fixed_point@0.0001");
  EXPECT_EQ(fixed.name(), "implicit_euler (fixed point)") << "tables and full labels keep the words";
  // Alone, at its own step or implicit_euler's --dt.
  const auto alone = parse_lanes("implicit_euler_fixed_point@1/60,implicit_euler_fixed_point", "implicit_euler=1e-3", 1e-4);
  ASSERT_EQ(alone.size(), 2u);
  EXPECT_TRUE(alone[0].fixed_point && alone[1].fixed_point);
  EXPECT_EQ(alone[0].dt, 1.0 / 60);
  EXPECT_EQ(alone[1].dt, 1e-3);
  EXPECT_NE(usage_error([] { parse_lanes("course,implicit_euler_fixed_point", "", 1e-4); }).find(
                "'implicit_euler_fixed_point@0.0001' is listed twice"),
            std::string::npos);
  // The reference is an integrator as the scene sets it up, not the course's variant.
  EXPECT_NE(usage_error([] { parse_reference("implicit_euler_fixed_point@1e-5", parse_lanes("rk4", "", 1e-3)); })
                .find("--reference: unknown integrator"),
            std::string::npos);
}

TEST(ParseLanes, TheLaneSettingsOfTheFixedPointLaneHaveTheCoursesSettings) {
  Model base;
  base.implicit.solver = ImplicitSolver::Newton;
  const Lane course = parse_lanes("course", "", 1e-4)[1];
  const MethodSettings m = lane_settings(base, course);
  EXPECT_EQ(m.implicit.solver, ImplicitSolver::FixedPoint);
  EXPECT_EQ(m.implicit.fixed_point_iterations, 1);
  const MethodSettings none = lane_settings(base, parse_lanes("implicit_euler", "", 1e-4)[0]);
  EXPECT_EQ(none.implicit.solver, ImplicitSolver::Newton) << "a lane without items runs the scene's settings";
  EXPECT_EQ(none.implicit.newton_max_iterations, base.implicit.newton_max_iterations);
}

TEST(ParseLanes, IterationsFollowAColonAndShowInLabelsAndSpellings) {
  const auto lanes = parse_lanes("xpbd@1/600:1,xpbd@1/60:10,implicit_euler@1/60:1,vbd:5", "", 1e-3);
  ASSERT_EQ(lanes.size(), 4u);
  EXPECT_EQ(lanes[0].iterations, 1);
  EXPECT_EQ(lanes[0].dt, 1.0 / 600);
  EXPECT_EQ(lanes[0].spelling(), "xpbd@1/600:1");
  EXPECT_EQ(lanes[1].label(), "xpbd:10  dt = 1/60 s");
  EXPECT_EQ(lanes[2].name(), "implicit_euler:1 (Baraff & Witkin)");
  EXPECT_EQ(lanes[3].dt, 1e-3);
  Model base;
  EXPECT_EQ(lane_settings(base, lanes[2]).implicit.newton_max_iterations, 1);
  EXPECT_EQ(lane_settings(base, lanes[3]).solvers.vbd.iterations, 5);
  const auto again = parse_lanes(lanes[0].spelling(), "", 1e-3);
  EXPECT_EQ(again[0].iterations, 1);
}

TEST(ParseLanes, ATolerancePicksTheResidualStopWithIterationsAsItsCap) {
  const auto lanes = parse_lanes("vbd@1/60:tol=1e-4,xpbd@1/60:200:tol=1e-3,projective_dynamics:tol=1e-5:50", "", 1e-3);
  ASSERT_EQ(lanes.size(), 3u);
  EXPECT_EQ(lanes[0].tolerance, 1e-4);
  EXPECT_EQ(lanes[0].iterations, 0);
  EXPECT_EQ(lanes[0].spelling(), "vbd@1/60:tol=0.0001");
  EXPECT_EQ(lanes[1].name(), "xpbd:200:tol=0.001");
  EXPECT_EQ(lanes[2].iterations, 50);
  Model base;
  const MethodSettings vbd = lane_settings(base, lanes[0]);
  EXPECT_EQ(vbd.solvers.vbd.tolerance, 1e-4);
  EXPECT_EQ(vbd.solvers.vbd.iterations, kToleranceCap);
  const MethodSettings xpbd = lane_settings(base, lanes[1]);
  EXPECT_EQ(xpbd.solvers.xpbd.tolerance, 1e-3);
  EXPECT_EQ(xpbd.solvers.xpbd.iterations, 200);
  const auto again = parse_lanes(lanes[1].spelling(), "", 1e-3);
  EXPECT_EQ(again[0].tolerance, 1e-3);
  EXPECT_EQ(again[0].iterations, 200);
  EXPECT_EQ(usage_error([] { parse_lanes("vbd:tol=1e-4,vbd", "", 1e-3); }), "") << "two lanes, not one twice";
}

TEST(ParseLanes, RefusesToleranceWhereThereIsNoResidualStopOrNoNumber) {
  for (const char* bad : {"vbd:tol=0", "vbd:tol=1", "vbd:tol=0.9", "vbd:tol=x", "vbd:tol="})
    EXPECT_NE(usage_error([&] { parse_lanes(bad, "", 1e-3); }).find("must be a number above 0 and at most 0.5"),
              std::string::npos) << bad;
  EXPECT_NE(usage_error([] { parse_lanes("implicit_euler:tol=1e-4", "", 1e-3); }).find("no residual tolerance"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("vbd:tol=1e-4:tol=1e-3", "", 1e-3); }).find("tol= twice"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("vbd:5:6", "", 1e-3); }).find("iterations twice"), std::string::npos);
}

TEST(ParseLanes, RefusesBadIterationCounts) {
  for (const char* bad : {"vbd:0", "vbd:-3", "vbd:ten", "vbd:1000001", "vbd:", "vbd@1/60:1.5"})
    EXPECT_NE(usage_error([&] { parse_lanes(bad, "", 1e-3); }).find("is not a whole number from 1 to 1000000"),
              std::string::npos) << bad;
  EXPECT_NE(usage_error([] { parse_lanes("rk4:3", "", 1e-3); }).find("rk4 has no iterations"), std::string::npos);
  EXPECT_EQ(usage_error([] { parse_lanes("vbd:5,vbd:6", "", 1e-3); }), "") << "two lanes, not one twice";
}

TEST(ParseLanes, RefusesBadItemsNamingTheOption) {
  EXPECT_NE(usage_error([] { parse_lanes("rk4@1e-4,rk4@1e-4", "", 1e-3); }).find("listed twice"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("rk4,rk4", "", 1e-3); }).find("listed twice"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("rk4@", "", 1e-3); }).find("no step after '@'"), std::string::npos);
  // course names four lanes: offered for --integrators, not for the one --reference lane.
  EXPECT_NE(usage_error([] { parse_lanes("rk9", "", 1e-3); }).find(", or course)"), std::string::npos);
  const std::string reference = usage_error([] { parse_reference("rk9@1e-5", parse_lanes("rk4", "", 1e-3)); });
  EXPECT_NE(reference.find("--reference: unknown integrator 'rk9'"), std::string::npos) << reference;
  EXPECT_EQ(reference.find("course"), std::string::npos) << reference;
  EXPECT_NE(usage_error([] { parse_lanes("rk4@fast", "", 1e-3); }).find("'fast' in 'rk4@fast' is not a number"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("rk4@0", "", 1e-3); }).find("must be > 0"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("rk4@-1", "", 1e-3); }).find("must be > 0"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("verlet@1e-3", "", 1e-3); }).find("--integrators: unknown integrator 'verlet'"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("", "", 1e-3); }).find("no integrator given"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("rk4,,midpoint", "", 1e-3); }).find("empty item"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_lanes("rk4@1e-4", "rk4=1e-3", 1e-3); }).find("has its own step"),
            std::string::npos)
      << "--dt for a lane that has @STEP";
}

TEST(ParseReference, DefaultsToRk4AtAQuarterOfTheSmallestStep) {
  const auto lanes = parse_lanes("explicit_euler@1e-4,implicit_euler@1/60", "", 1e-3);
  const Lane ref = parse_reference("", lanes);
  EXPECT_EQ(ref.kind, IntegratorKind::Rk4);
  EXPECT_EQ(ref.dt, 2.5e-5);
  const Lane given = parse_reference("midpoint@1e-6", lanes);
  EXPECT_EQ(given.kind, IntegratorKind::Midpoint);
  EXPECT_EQ(given.dt, 1e-6);
  EXPECT_EQ(parse_reference("symplectic_euler", lanes).dt, 2.5e-5);
  EXPECT_NE(usage_error([&] { parse_reference("rk4@1e-6,midpoint", lanes); }).find("one lane"), std::string::npos);
  EXPECT_NE(usage_error([&] { parse_reference("nope@1", lanes); }).find("--reference: unknown integrator"),
            std::string::npos);
}

TEST(ParseStudyLanes, TakesCompareLanesWithoutStepsAndSpellsThemWithout) {
  const std::vector<Lane> lanes = parse_study_lanes("course,xpbd:10,implicit_euler:1", "no step");
  std::vector<std::string> spelt;
  for (const Lane& l : lanes) spelt.push_back(l.stepless_spelling());
  EXPECT_EQ(spelt, (std::vector<std::string>{"explicit_euler", "implicit_euler_fixed_point", "midpoint", "rk4",
                                             "xpbd:10", "implicit_euler:1"}));
  EXPECT_EQ(usage_error([] { parse_study_lanes("rk4@1e-3", "no step"); }), "--integrators: 'rk4@1e-3': no step");
  EXPECT_EQ(usage_error([] { parse_study_lanes("course,rk4", "no step"); }), "--integrators: 'rk4' is listed twice");
}

namespace {

// A small sheet, gentle enough for the course's fixed point at its 1 ms step.
const char* kSheet = R"(
name: sheet
dt: 1.0e-3
duration: 0.2
cloth: {particles: [6, 6], size: [1, 1], particle_mass: 0.1, pinned: corners,
        springs: {structural: {stiffness: 100, damping: 0.5}, shear: {stiffness: 50, damping: 0.2}}}
)";

State run_until(const Model& model, IntegratorKind kind, double dt, const MethodSettings& settings, double t) {
  Run run(model, kind, dt, settings);
  EXPECT_TRUE(run.advance_to(t)) << integrator_name(kind);
  return run.state();
}

bool same_bits(const State& a, const State& b) {
  return a.step == b.step && a.x.size() == b.x.size() && a.x.cwiseEqual(b.x).all() && a.v.cwiseEqual(b.v).all();
}

}  // namespace

// A lane's items become the settings its Run carries on the scene's own model; a scene whose
// blocks (or whose integrator: key) say the same values runs the model's defaults. Both must
// reach the same state to the bit, and it must differ from the scene's plain settings.
TEST(LaneSettings, ALanesItemsRunAsTheSameValuesInTheScenesBlocks) {
  struct Case {
    const char* lane;
    const char* scene;  // what the scene says instead
  };
  const Case cases[] = {
      {"xpbd@1/60:5", "integrator: xpbd\nxpbd: {iterations: 5}\n"},
      {"vbd:tol=1e-4", "integrator: vbd\nvbd: {tolerance: 1.0e-4, iterations: 1000}\n"},
      {"newmark@1/60:beta=0.3", "integrator: newmark:beta=0.3\n"},  // no block: the integrator key's lane
      {"dopri5:tol=1e-8", "integrator: dopri5:tol=1e-8\n"},
      {"implicit_euler_fixed_point", "integrator: implicit_euler\nimplicit: {solver: fixed_point, iterations: 1}\n"},
  };
  const Model plain = build_model(parse_scene(kSheet, "sheet.yaml"));
  for (const Case& c : cases) {
    const Lane lane = parse_lanes(c.lane, "", plain.dt)[0];
    const State by_lane = run_until(plain, lane.kind, lane.dt, lane_settings(plain, lane), 0.2);
    const Model blocks = build_model(parse_scene(std::string(kSheet) + c.scene, "blocks.yaml"));
    const State by_scene = run_until(blocks, lane.kind, lane.dt, blocks.method_defaults(), 0.2);
    EXPECT_TRUE(same_bits(by_lane, by_scene)) << c.lane;
    EXPECT_FALSE(same_bits(by_lane, run_until(plain, lane.kind, lane.dt, plain.method_defaults(), 0.2)))
        << c.lane << ": the lane's settings changed nothing";
  }
}

// Two lanes of one scene with different settings run on that scene's Model itself: nothing
// is copied, so "the same model" is one address.
TEST(LaneSettings, TwoLanesRunOnOneModelWithTheirOwnSettings) {
  const Model model = build_model(parse_scene(kSheet, "sheet.yaml"));
  const std::vector<Lane> lanes = parse_lanes("xpbd:5,xpbd:20,implicit_euler_fixed_point", "", model.dt);
  std::vector<std::unique_ptr<clothsim::Run>> runs;  // (gtest's Test::Run hides the name)
  for (const Lane& l : lanes)
    runs.push_back(std::make_unique<clothsim::Run>(model, l.kind, l.dt, lane_settings(model, l)));
  for (const auto& r : runs) EXPECT_EQ(&r->model(), &model);
  EXPECT_EQ(runs[0]->settings().solvers.xpbd.iterations, 5);
  EXPECT_EQ(runs[1]->settings().solvers.xpbd.iterations, 20);
  EXPECT_EQ(runs[2]->settings().implicit.solver, ImplicitSolver::FixedPoint);
  EXPECT_EQ(model.solvers.xpbd.iterations, XpbdDef{}.iterations) << "the model keeps the scene's";
  EXPECT_EQ(model.implicit.solver, ImplicitSolver::Newton);
}

TEST(LaneSettings, RefusesAProjectingSolverOnABarrierSceneNamingTheOption) {
  const Model barrier =
      build_model(parse_scene(std::string(kSheet) + "collision: {model: barrier}\nground: {height: -1}\n", "b.yaml"));
  const std::string m = usage_error([&] { lane_settings(barrier, parse_lanes("xpbd:5", "", barrier.dt)[0]); });
  EXPECT_EQ(m.rfind("--integrators: collision.model: barrier: xpbd has no barrier contact", 0), 0u) << m;
  EXPECT_NO_THROW(lane_settings(barrier, parse_lanes("vbd:5", "", barrier.dt)[0]));
}
