// stability's plan (src/clip/studies/stability_plan.h), the one the CLI and the Python module
// both make: the default values, T and step range, and each case's models.
#include "clip/studies/stability_plan.h"

#include <gtest/gtest.h>

#include "clip/common/cli_common.h"
#include "core/model/stiffness_estimate.h"
#include "scene/scene_parser.h"
#include "test_support.h"

namespace clothsim::clip {
namespace {

TEST(PlanStability, WithOnlyASceneSweepsItsStiffnessOverFourDecadesWithinTheDefaultRange) {
  StabilityOptions o;
  o.scene.path = testing::scene_path("spring.yaml");  // ks = 100 N/m, dt = 1e-3 s, duration 2 s
  const SceneDef base = load_scene(o.scene.path, {});
  StabilityStudy study = plan_stability(o, base);
  EXPECT_EQ(study.values, (std::vector<double>{100, 1e3, 1e4, 1e5, 1e6}));
  ASSERT_EQ(study.cases.size(), 5u);
  EXPECT_DOUBLE_EQ(study.spec.duration, kStabilityDefaultDuration);
  EXPECT_DOUBLE_EQ(study.spec.max_dt, std::min(kStabilityDefaultDuration / kMinStepsAtMaxDt, kMaxDtOverSceneDt * base.dt));
  // The smallest step tried: below the stiffest case's explicit limit, by kMinDtDivisor.
  const double stiffest = analysis::estimate_stiffness(study.cases.back().model).dt_with_damping();
  EXPECT_DOUBLE_EQ(study.spec.min_dt, std::min(base.dt, stiffest) / kMinDtDivisor);
  EXPECT_EQ(study.names.size(), study.spec.integrators.size());
}

TEST(PlanStability, RefsPointAtEachCasesModelWithEachLanesOwnSettings) {
  StabilityOptions o;
  o.scene.path = testing::scene_path("spring.yaml");
  o.integrators = "rk4,implicit_euler:2";
  o.values = "100,400";
  StabilityStudy study = plan_stability(o, load_scene(o.scene.path, {}));
  const std::vector<analysis::StabilityCase> refs = study.refs();
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_EQ(refs[1].value, 400);
  EXPECT_EQ(refs[1].model, &study.cases[1].model);
  ASSERT_EQ(refs[1].lane_settings.size(), 2u);
  const int scene_cap = study.cases[1].model.implicit.newton_max_iterations;
  EXPECT_EQ(refs[1].lane_settings[0].implicit.newton_max_iterations, scene_cap);
  EXPECT_EQ(refs[1].lane_settings[1].implicit.newton_max_iterations, 2) << "implicit_euler:2 has its own Newton cap";
  EXPECT_NE(scene_cap, 2);
}

TEST(PlanStability, RefusesABadOptionNamingIt) {
  StabilityOptions o;
  o.scene.path = testing::scene_path("spring.yaml");
  const SceneDef base = load_scene(o.scene.path, {});
  o.integrators = "rk4@1e-3";
  EXPECT_THROW(plan_stability(o, base), UsageError);
  o.integrators = "rk4";
  o.param = "cloth.no_such_key";  // the scene's parser's error, of --param as typed (as with --values)
  try {
    plan_stability(o, base);
    ADD_FAILURE() << "an unknown --param accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(": --param cloth.no_such_key: unknown key"), std::string::npos) << e.what();
  }
  o.param = "ks";
  o.min_dt = -1.0;
  EXPECT_THROW(plan_stability(o, base), UsageError);
}

}  // namespace
}  // namespace clothsim::clip
