// The options every scene-reading subcommand shares, parsed without running the binary.
#include "clip/common/scene_options.h"

#include <gtest/gtest.h>

#include <functional>

#include "clip/common/cli_common.h"
#include "cli/usage_error.h"
#include "scene/scene_parser.h"

using namespace clothsim;
using namespace clothsim::clip;
using clothsim::testing::usage_error;

namespace {

TEST(ParseIntegratorList, KeepsTheOrderGiven) {
  const auto kinds = parse_integrator_list("rk4,explicit_euler, midpoint");
  ASSERT_EQ(kinds.size(), 3u);
  EXPECT_EQ(kinds[0], IntegratorKind::Rk4);
  EXPECT_EQ(kinds[1], IntegratorKind::ExplicitEuler);
  EXPECT_EQ(kinds[2], IntegratorKind::Midpoint);
}

TEST(ParseIntegratorList, RejectsUnknownRepeatedAndEmptyNamesNamingTheOption) {
  EXPECT_NE(usage_error([] { parse_integrator_list("rk4,verlet", "--integrators"); }).find("--integrators: unknown"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_integrator_list("rk4,verlet"); }).find("unknown integrator 'verlet'"),
            std::string::npos);
  EXPECT_NE(usage_error([] { parse_integrator_list("rk4,rk4"); }).find("listed twice"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_integrator_list("rk4,,midpoint"); }).find("empty"), std::string::npos);
  EXPECT_NE(usage_error([] { parse_integrator_list(""); }).find("no integrator given"), std::string::npos);
}

TEST(LoadSceneWithOptions, AppliesSetThenDurationDtAndIntegrator) {
  SceneOptions o;
  o.path = std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml";
  o.sets = {"cloth.springs.structural.stiffness=400"};
  o.duration = 0.5;
  o.dt = 2e-3;
  o.integrator = "rk4";
  const SceneDef s = load_scene_with_options(o);
  EXPECT_DOUBLE_EQ(s.cloth.structural->stiffness, 400);
  EXPECT_DOUBLE_EQ(s.duration, 0.5);
  EXPECT_DOUBLE_EQ(s.dt, 2e-3);
  EXPECT_EQ(s.integrator, IntegratorKind::Rk4);
}

TEST(LoadSceneWithOptions, RejectsNonPositiveStepsAndNegativeDurations) {
  SceneOptions o;
  o.path = std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml";
  o.dt = 0.0;
  EXPECT_NE(usage_error([&] { load_scene_with_options(o); }).find("--dt: must be"), std::string::npos);
  o.dt.reset();
  o.duration = -1.0;
  EXPECT_NE(usage_error([&] { load_scene_with_options(o); }).find("--duration: must be"), std::string::npos);
  o.duration.reset();
  o.integrator = "verlet";
  EXPECT_NE(usage_error([&] { load_scene_with_options(o); }).find("--integrator: unknown integrator 'verlet'"),
            std::string::npos);
}

TEST(LoadSceneWithOptions, BoundsTheRunOnceDurationAndDtAreIn) {
  // The file's 5 s at --set dt=1e-9 would be 5e9 steps, but --duration 1 makes it 1e9: the
  // limit applies to the run asked for, not to the file's duration it replaces.
  SceneOptions o;
  o.path = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";
  o.sets = {"dt=1e-9"};
  o.duration = 1.0;
  EXPECT_EQ(usage_error([&] { load_scene_with_options(o); }), "");
  o.duration = 2.0;
  EXPECT_NE(usage_error([&] { load_scene_with_options(o); }).find("--duration: duration / dt = 2 s / 1e-09 s"),
            std::string::npos);
  o.sets.clear();
  o.duration.reset();
  o.dt = 1e-12;
  EXPECT_NE(usage_error([&] { load_scene_with_options(o); }).find("--dt: duration / dt"), std::string::npos);
}

}  // namespace
