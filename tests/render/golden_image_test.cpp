// The golden-image tolerance (imgdiff's defaults, which `clothsim golden check` and the
// project's golden images, tests/golden/manifest.yaml, use) checked both ways on the drape
// frame of the project's goldens: re-rendering passes it, and a real change to the picture
// (a sphere moved by 10 cm, another cloth colour, a missing shadow) fails it.
// The golden images themselves are checked through `clothsim golden check` (tests/cli/cmd_golden_test.cpp).
#include <gtest/gtest.h>

#include <string>

#include "image_diff.h"
#include "renderer.h"
#include "scene_parser.h"
#include "simulation.h"
#include "snapshot.h"

namespace clothsim {
namespace {

struct GoldenCase {
  const char* scene;  // scenes/<scene>.yaml
  double t;           // s
};

const GoldenCase kDrape{"drape", 1.5};

Renderer& renderer() {
  static Renderer r;
  return r;
}

RenderFrame scene_frame(const GoldenCase& c) {
  const SceneDef scene = load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/" + c.scene + ".yaml");
  const Model model = build_model(scene);
  Run run(model, scene.integrator, scene.dt);
  EXPECT_TRUE(run.advance_to(c.t)) << c.scene << " diverged";
  SnapshotText text;
  text.lines = overlay_lines(model, scene.integrator, scene.dt, run.state().t);
  RenderFrame frame = make_render_frame(model, run.state(), text);
  frame.width = 320;
  frame.height = 180;
  return frame;
}

// The tolerance separates noise from change, on the drape frame.
class GoldenTolerance : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    frame_ = new RenderFrame(scene_frame(kDrape));
    reference_ = new Image(renderer().render(*frame_));
  }
  static void TearDownTestSuite() {
    delete frame_;
    delete reference_;
  }
  static bool passes(const RenderFrame& changed) {
    const DiffTolerance tolerance;
    return within_tolerance(compare_images(*reference_, renderer().render(changed), tolerance.pixel_threshold),
                            tolerance);
  }
  static RenderFrame* frame_;
  static Image* reference_;
};
RenderFrame* GoldenTolerance::frame_ = nullptr;
Image* GoldenTolerance::reference_ = nullptr;

TEST_F(GoldenTolerance, ReRenderingPasses) { EXPECT_TRUE(passes(*frame_)); }

TEST_F(GoldenTolerance, ASphereMovedByTenCentimetresFails) {
  RenderFrame moved = *frame_;
  ASSERT_FALSE(moved.spheres.empty());
  moved.spheres[0].center[0] += 0.1f;
  EXPECT_FALSE(passes(moved));
}

TEST_F(GoldenTolerance, ADifferentClothColourFails) {
  RenderFrame recoloured = *frame_;
  recoloured.cloth_front = {0.35f, 0.45f, 0.70f};
  EXPECT_FALSE(passes(recoloured));
}

TEST_F(GoldenTolerance, AMissingShadowFails) {
  RenderFrame unshadowed = *frame_;
  unshadowed.shadows = false;
  EXPECT_FALSE(passes(unshadowed));
}

TEST_F(GoldenTolerance, ADifferentTimeInTheOverlayFails) {
  RenderFrame relabelled = *frame_;
  ASSERT_FALSE(relabelled.overlay_lines.empty());
  relabelled.overlay_lines.back() = "t = 9.999 s";
  // Text is small: RMS stays low, but the changed glyph pixels differ strongly. Caught by
  // a strict share of pixels (imgdiff --max-over 0), not by the default tolerance.
  const DiffStats stats = compare_images(*reference_, renderer().render(relabelled), 16);
  EXPECT_GT(stats.over_fraction, 0.0);
  EXPECT_GT(stats.max, 100);
}

}  // namespace
}  // namespace clothsim
