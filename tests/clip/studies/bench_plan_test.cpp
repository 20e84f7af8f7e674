// bench's plan (src/clip/studies/bench_plan.h), the one the CLI and the Python module both make:
// the default steps and T, the lanes as the scene runs them, and the options it refuses.
#include "clip/studies/bench_plan.h"

#include <gtest/gtest.h>

#include "clip/common/cli_common.h"
#include "scene/scene_parser.h"
#include "test_support.h"

namespace clothsim::clip {
namespace {

BenchOptions options_for(const std::string& scene) {
  BenchOptions o;
  o.scene.path = testing::scene_path(scene);
  return o;
}

TEST(DefaultDuration, IsTheSmallestCapRoundedDownToAWholeNumberOfTheLargestStep) {
  // Caps: the scene's 2 s, 0.5 s, 8000 x 1e-5 = 0.08 s; 0.08 / 3e-3 = 26.7 -> 26 steps.
  EXPECT_DOUBLE_EQ(default_duration(2.0, {1e-5, 3e-3}), 26 * 3e-3);
  EXPECT_DOUBLE_EQ(default_duration(0.3, {1e-3, 2e-2}), 0.3) << "the scene's duration is a whole 15 steps";
  EXPECT_DOUBLE_EQ(default_duration(5.0, {1e-3, 1e-2}), 0.5) << "never more than kMaxDefaultDuration";
}

TEST(DefaultDuration, RefusesAStepLongerThanTheCapNamingDts) {
  try {
    default_duration(2.0, {1e-5, 0.1});
    FAIL() << "0.1 s does not fit in 8000 x 1e-5 s";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--dts: the largest step 0.1 s"), std::string::npos) << e.what();
  }
}

TEST(PlanBench, WithOnlyASceneSweepsSixStepsAroundItsDtToTheDefaultT) {
  const BenchOptions o = options_for("spring.yaml");
  const SceneDef scene = load_scene(o.scene.path, {});
  const std::vector<Lane> lanes = bench_lanes(o, scene);
  const WorkPrecisionSpec spec = plan_bench(o, scene, lanes);
  ASSERT_EQ(spec.dts.size(), std::size(kDefaultStepFactors));
  for (std::size_t i = 0; i < spec.dts.size(); ++i) EXPECT_DOUBLE_EQ(spec.dts[i], kDefaultStepFactors[i] * scene.dt);
  EXPECT_DOUBLE_EQ(spec.duration, default_duration(scene.duration, spec.dts));
  EXPECT_EQ(spec.lane_names, (LaneNames{"explicit_euler", "implicit_euler", "midpoint", "rk4"}));
  for (double dt : spec.frame_dts) {  // only the frame steps that divide T
    const double n = spec.duration / dt;
    EXPECT_NEAR(n, std::round(n), 1e-9 * n);
  }
}

TEST(PlanBench, NamesTheCoursesFixedPointAsItselfNotAsBackwardEuler) {
  BenchOptions o = options_for("spring.yaml");
  o.integrators = "course";
  const SceneDef scene = load_scene(o.scene.path, {});
  EXPECT_EQ(plan_bench(o, scene, bench_lanes(o, scene)).lane_names,
            (LaneNames{"explicit_euler", "implicit_euler_fixed_point", "midpoint", "rk4"}));
}

TEST(PlanBench, RefusesAStepAndNamesTheOption) {
  BenchOptions o = options_for("spring.yaml");
  const SceneDef scene = load_scene(o.scene.path, {});
  o.integrators = "rk4@1e-3";
  EXPECT_THROW(bench_lanes(o, scene), UsageError) << "bench sweeps the step: a lane takes no @STEP";
  o.integrators = "rk4";
  o.dts = "1e-3,-2e-3";
  EXPECT_THROW(plan_bench(o, scene, bench_lanes(o, scene)), UsageError);
  o.dts = std::nullopt;
  o.scene.duration = 0.0;
  EXPECT_THROW(plan_bench(o, scene, bench_lanes(o, scene)), UsageError);
}

TEST(AttachLaneSettings, GivesALaneWithItsOwnIterationsItsOwnSettingsOnTheScenesModel) {
  BenchOptions o = options_for("spring.yaml");
  o.integrators = "rk4,vbd:3";
  SceneDef scene = load_scene(o.scene.path, {});
  const std::vector<Lane> lanes = bench_lanes(o, scene);
  WorkPrecisionSpec spec = plan_bench(o, scene, lanes);
  const Model model = build_bench_model(o, scene, lanes, spec);
  EXPECT_GE(scene.duration, spec.duration) << "the scene runs to T at least";
  attach_lane_settings(model, lanes, spec);
  ASSERT_EQ(spec.lane_settings.size(), 2u);
  EXPECT_EQ(spec.lane_settings[0].solvers.vbd.iterations, model.solvers.vbd.iterations) << "rk4: the scene's";
  EXPECT_EQ(spec.lane_settings[1].solvers.vbd.iterations, 3) << "vbd:3 runs with its own iterations";
  EXPECT_NE(model.solvers.vbd.iterations, 3) << "and the model keeps the scene's";
}

TEST(PlanScale, TakesLanesWithStepsAndWholeSidesAndRefusesTheRest) {
  BenchOptions o = options_for("drape.yaml");
  o.integrators = "symplectic_euler@1e-4,rk4";
  o.scale = "4,6";
  const ScalePlan plan = plan_scale(o);
  EXPECT_EQ(plan.sides, (std::vector<int>{4, 6}));
  ASSERT_EQ(plan.spec.lanes.size(), 2u);
  EXPECT_EQ(plan.spec.lanes[0].dt, 1e-4);
  EXPECT_EQ(plan.spec.lanes[1].dt, plan.spec.sizes.front().scene.dt) << "a lane without @STEP: the scene's dt";
  EXPECT_LE(plan.spec.duration, kMaxScaleDuration);
  o.scale = "4,6.5";
  EXPECT_THROW(plan_scale(o), UsageError) << "half a particle";
  o.scale = "4";
  o.dts = "1e-3";
  EXPECT_THROW(plan_scale(o), UsageError) << "--dts does not apply to --scale";
}

}  // namespace
}  // namespace clothsim::clip
