// The lane: one grammar, one parser, and the scene's `integrator:` key as one of its doors.
// (The other doors, run, compare, bench, stability and Python, run the same strings in
// tests/cli/lane_doors_test.cpp and tests/python/test_clothsim.py.)
#include "scene/lane.h"

#include <gtest/gtest.h>

#include "scene/scene_def.h"
#include "scene/scene_parser.h"

namespace clothsim {
namespace {

std::string refusal(const std::string& text) {
  try {
    parse_lane(text);
  } catch (const LaneError& e) {
    return e.what();
  }
  return "";
}

TEST(Lane, ParsesNameStepIterationsAndToleranceInAnyOrder) {
  const Lane a = parse_lane("xpbd@1/60:5");
  EXPECT_EQ(a.kind, IntegratorKind::Xpbd);
  EXPECT_EQ(a.dt, 1.0 / 60);
  EXPECT_EQ(a.step_text, "1/60");
  EXPECT_EQ(a.step_from, StepFrom::Written);
  EXPECT_EQ(a.iterations, 5);
  const Lane b = parse_lane(" vbd @ 1e-3 : tol = 1e-4 : 50 ");
  EXPECT_EQ(b.kind, IntegratorKind::Vbd);
  EXPECT_EQ(b.dt, 1e-3);
  EXPECT_EQ(b.tolerance, 1e-4);
  EXPECT_EQ(b.iterations, 50);
  const Lane c = parse_lane("vbd:10");
  EXPECT_EQ(c.dt, 0.0) << "no @STEP: the door's step";
  EXPECT_EQ(c.step_from, StepFrom::Scene);
  EXPECT_TRUE(c.free_step());
  const Lane fixed = parse_lane("implicit_euler_fixed_point");
  EXPECT_EQ(fixed.kind, IntegratorKind::ImplicitEuler);
  EXPECT_TRUE(fixed.fixed_point);
}

TEST(Lane, SpellsItselfAsItParses) {
  for (const char* text : {"rk4@2e-4", "xpbd@1/60:5", "vbd@1/60:tol=0.0001", "implicit_euler@1/60:1",
                           "implicit_euler_fixed_point@0.001", "projective_dynamics@1/600:20:tol=0.001"}) {
    const Lane lane = parse_lane(text);
    EXPECT_EQ(lane.spelling(), text);
    EXPECT_TRUE(parse_lane(lane.spelling()).same_as(lane)) << text;
  }
  EXPECT_EQ(parse_lane("vbd:10").stepless_spelling(), "vbd:10");
  // Every figure kept: the spelling is the same lane, not a rounding of it.
  const Lane fine = parse_lane("newmark@1/60:beta=0.2777777777777778:gamma=0.55");
  EXPECT_TRUE(parse_lane(fine.spelling()).same_as(fine)) << fine.spelling();
}

TEST(Lane, RefusesWhatNoMethodTakesWithOneLineSayingWhy) {
  EXPECT_NE(refusal("rk9").find("unknown integrator 'rk9' (expected one of:"), std::string::npos);
  EXPECT_NE(refusal("rk9").find("implicit_euler_fixed_point"), std::string::npos) << "the fixed point is a lane name";
  EXPECT_NE(refusal("rk4:3").find("rk4 has no iterations to set"), std::string::npos);
  EXPECT_NE(refusal("rk4@1/ 60").find("is not a number"), std::string::npos) << "a space inside a number";
  EXPECT_NE(refusal("vbd:tol=0.9").find("at most 0.5"), std::string::npos) << "as the scene's vbd.tolerance";
  EXPECT_NE(refusal("vbd:rho=0.5").find("vbd has no parameter 'rho'"), std::string::npos);
  EXPECT_NE(refusal("implicit_euler:tol=1e-3").find("no residual tolerance"), std::string::npos);
  EXPECT_NE(refusal("vbd:0").find("is not a whole number from 1 to 1000000"), std::string::npos);
  EXPECT_EQ(refusal("rk4@1e-3 "), "") << "spaces around the pieces are ignored";
}

TEST(Lane, AnAdaptivePairTakesItsTolerancesAndItsStepAsAFirstTrial) {
  const Lane both = parse_lane("dopri5:tol=1e-8");
  EXPECT_EQ(both.rtol, 1e-8);
  EXPECT_EQ(both.atol, 1e-8);
  EXPECT_EQ(both.tolerance, 0.0) << "a pair's tol= is its error control, not a residual";
  EXPECT_EQ(both.stepless_spelling(), "dopri5:tol=1e-08");
  EXPECT_FALSE(both.free_step()) << "--match never re-steps an adaptive pair";
  EXPECT_EQ(both.landing_grid(), 0.0) << "it lands on every target exactly";
  const Lane split = parse_lane("rkf78@1e-3:rtol=1e-9:atol=1e-7");
  EXPECT_EQ(split.rtol, 1e-9);
  EXPECT_EQ(split.atol, 1e-7);
  EXPECT_EQ(split.spelling(), "rkf78@1e-3:rtol=1e-09:atol=1e-07");
  EXPECT_TRUE(parse_lane(split.spelling()).same_as(split));
  EXPECT_NE(refusal("rk4:rtol=1e-6").find("rk4 has no error control to set"), std::string::npos);
  EXPECT_NE(refusal("bs3:tol=1e-6:rtol=1e-7").find("tol= sets both"), std::string::npos);
  EXPECT_NE(refusal("dopri5:tol=1").find("above 0 and below 1"), std::string::npos);
  EXPECT_EQ(refusal("dopri5:tol=0.9"), "") << "a pair's tolerance is not a residual's, bounded by 0.5";
  EXPECT_NE(refusal("dopri5:3").find("dopri5 has no iterations to set"), std::string::npos);
  SceneDef scene;
  apply_lane(scene, split);
  EXPECT_EQ(scene.adaptive.rtol, 1e-9);
  EXPECT_EQ(scene.adaptive.atol, 1e-7);
}

TEST(Lane, AMethodsOwnParametersAreKeyValueItemsItsRowNames) {
  const Lane n = parse_lane("newmark@1/60:beta=0.3:gamma=0.6");
  ASSERT_EQ(n.params.size(), 2u);
  EXPECT_EQ(n.params[0], (std::pair<std::string, double>{"beta", 0.3}));
  EXPECT_EQ(n.spelling(), "newmark@1/60:beta=0.3:gamma=0.6");
  EXPECT_TRUE(parse_lane(n.spelling()).same_as(n));
  EXPECT_FALSE(parse_lane("newmark@1/60").same_as(n)) << "other parameters, another lane";
  SceneDef scene;
  apply_lane(scene, n);
  EXPECT_EQ(scene.methods.newmark.beta, 0.3);
  EXPECT_EQ(scene.methods.newmark.gamma, 0.6);
  apply_lane(scene, parse_lane("generalized_alpha:rho=0"));
  EXPECT_EQ(scene.methods.generalized_alpha.rho_inf, 0.0) << "rho_inf = 0 is a value, not unset";
  EXPECT_NE(refusal("rk4:rho=0.5").find("rk4 has no parameter 'rho'"), std::string::npos);
  EXPECT_NE(refusal("newmark:rho=0.5").find("newmark takes beta,gamma"), std::string::npos);
  EXPECT_NE(refusal("generalized_alpha:rho=1.5").find("rho (rho_inf) must be from 0 to 1"), std::string::npos);
  EXPECT_NE(refusal("newmark:gamma=0.4").find("gamma must be from 0.5 to 1"), std::string::npos);
  EXPECT_NE(refusal("newmark:beta=0").find("beta must be above 0"), std::string::npos);
  EXPECT_NE(refusal("newmark:beta=x").find("'x' in 'newmark:beta=x' is not a number"), std::string::npos);
  EXPECT_NE(refusal("newmark:beta=0.3:beta=0.25").find("gives beta= twice"), std::string::npos);
}

TEST(Lane, ListsExpandTheCourseAndKeepTheirOrder) {
  const std::vector<Lane> lanes = parse_lane_list("course,xpbd@1/60:5");
  ASSERT_EQ(lanes.size(), 5u);
  EXPECT_TRUE(lanes[1].fixed_point);
  EXPECT_EQ(lanes[4].iterations, 5);
}

TEST(Lane, AppliedToASceneSetsWhatTheFileWouldHaveSaid) {
  SceneDef scene;
  scene.dt = 1e-4;
  apply_lane(scene, parse_lane("xpbd@1/60:5"));
  EXPECT_EQ(scene.integrator, IntegratorKind::Xpbd);
  EXPECT_EQ(scene.dt, 1.0 / 60);
  EXPECT_EQ(scene.solvers.xpbd.iterations, 5);
  apply_lane(scene, parse_lane("vbd:tol=1e-4"));
  EXPECT_EQ(scene.dt, 1.0 / 60) << "no @STEP: the scene keeps its step";
  EXPECT_EQ(scene.solvers.vbd.tolerance, 1e-4);
  EXPECT_EQ(scene.solvers.vbd.iterations, kToleranceCap);
  apply_lane(scene, parse_lane("implicit_euler_fixed_point:3"));
  EXPECT_EQ(scene.implicit.solver, ImplicitSolver::FixedPoint);
  EXPECT_EQ(scene.implicit.fixed_point_iterations, 3);
}

const char* kSheet = R"(cloth:
  particles: [4, 4]
  size: [1, 1]
  particle_mass: 0.1
  springs:
    structural: {stiffness: 100, damping: 1}
)";

TEST(Lane, TheScenesIntegratorKeyTakesTheSameGrammar) {
  const SceneDef s = parse_scene(std::string("integrator: xpbd@1/60:5\n") + kSheet, "lane.yaml");
  EXPECT_EQ(s.integrator, IntegratorKind::Xpbd);
  EXPECT_EQ(s.dt, 1.0 / 60);
  EXPECT_EQ(s.solvers.xpbd.iterations, 5);
  const SceneDef f = parse_scene(std::string("integrator: implicit_euler_fixed_point\n") + kSheet, "lane.yaml");
  EXPECT_EQ(f.implicit.solver, ImplicitSolver::FixedPoint);
}

TEST(Lane, TheScenesKeyRefusesSayingOneThingTwiceNamingTheLine) {
  const auto error = [](const std::string& yaml) -> std::string {
    try {
      parse_scene(yaml, "lane.yaml");
    } catch (const SceneError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error(std::string("integrator: rk9\n") + kSheet).rfind("lane.yaml:1: integrator: unknown integrator 'rk9'", 0), 0u);
  EXPECT_NE(error(std::string("dt: 1e-3\nintegrator: rk4@2e-4\n") + kSheet)
                .find("lane.yaml:2: integrator: 'rk4@2e-4' gives the step, and so does dt (line 1)"),
            std::string::npos);
  EXPECT_NE(error(std::string("integrator: vbd:10\nvbd: {iterations: 20}\n") + kSheet)
                .find("sets vbd's solver, and so does the vbd: block (line 2)"),
            std::string::npos);
}

}  // namespace
}  // namespace clothsim
