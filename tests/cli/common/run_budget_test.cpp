// The peak memory of a one-lane run (tools/cli/common/run_budget.h), which `run` and `golden` check
// against --max-memory: each part counted only where the run has it.
#include "cli/common/run_budget.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "scene/memory_estimate.h"
#include "scene/scene_parser.h"

namespace clothsim::cli {
namespace {

SceneDef drape() { return load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml"); }

TEST(RunBudget, WithoutPicturesIsTheProcessTheModelAndTheLane) {
  const SceneDef scene = drape();
  const double expected = kProcessBytes + model_bytes(scene) + run_bytes(scene, scene.integrator) + kLaneThreadBytes;
  EXPECT_DOUBLE_EQ(run_budget(scene, PictureLook{}, {}).total(), expected);
}

TEST(RunBudget, PicturesAddTheRendererAtTheirSizeAndAVideoItsEncoder) {
  const SceneDef scene = drape();
  const double bare = run_budget(scene, PictureLook{}, {}).total();
  const double still = run_budget(scene, PictureLook{}, {true, 4000, 4000, false}).total();
  EXPECT_DOUBLE_EQ(still - bare, kRendererBytes + render_bytes(4000, 4000, scene.render.samples) + 4.0 * 4000 * 4000 * 4);
  const double video = run_budget(scene, PictureLook{}, {true, 4000, 4000, true}).total();
  EXPECT_DOUBLE_EQ(video - still, encoder_bytes(4000, 4000));
}

TEST(RunBudget, ErrorColouringAddsItsReferenceLaneAndTheHeldFirstSecond) {
  const SceneDef scene = drape();
  PictureLook look;
  look.color = FieldKind::Error;
  look.reference = LaneSpec{IntegratorKind::Rk4, scene.dt / 4, "", false};
  const double plain = run_budget(scene, PictureLook{}, {true, 320, 180, false}).total();
  const double coloured = run_budget(scene, look, {true, 320, 180, false}).total();
  EXPECT_DOUBLE_EQ(coloured - plain, run_bytes(scene, IntegratorKind::Rk4) + kLaneThreadBytes +
                                         held_frames_bytes(scene, 1, std::min(1.0, scene.duration) * scene.render.fps + 1.0));
}

}  // namespace
}  // namespace clothsim::cli
