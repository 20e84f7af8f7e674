// Golden images of the shipped scenes at fixed times, 320x180: scene -> engine -> snapshot ->
// renderer, compared with compare_images() at the tolerance `clothsim imgdiff` uses by default.
// On a mismatch the actual image and an amplified diff are written to CLOTHSIM_TEST_OUTPUT_DIR
// and named in the failure. CLOTHSIM_UPDATE_GOLDEN=1 rewrites tests/golden/ instead of comparing.
//
// The tolerance is checked both ways: re-rendering passes it, and a real change to the
// picture (a sphere moved by 10 cm, another cloth colour, a missing shadow) fails it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "image_diff.h"
#include "png_io.h"
#include "renderer.h"
#include "scene_parser.h"
#include "simulation.h"
#include "snapshot.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

struct GoldenCase {
  const char* scene;  // scenes/<scene>.yaml
  double t;           // s
};

// Simulated for ~1 s each at the scenes' own dt: a few seconds for the whole file.
const GoldenCase kCases[] = {{"drape", 1.5}, {"four_balls", 1.0}, {"curtain", 1.0}};

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

bool updating_goldens() {
  const char* v = std::getenv("CLOTHSIM_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

std::string golden_path(const GoldenCase& c) {
  return std::string(CLOTHSIM_GOLDEN_DIR) + "/" + c.scene + "_t" + std::to_string(static_cast<int>(c.t * 1000)) + "ms.png";
}

// Compares against the golden image; on failure writes the evidence and says where.
::testing::AssertionResult matches_golden(const std::string& golden, const Image& actual, const std::string& tag) {
  const Image expected = read_png(golden);
  const fs::path out = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / "golden";
  if (expected.width != actual.width || expected.height != actual.height) {
    fs::create_directories(out);
    write_png((out / (tag + "_actual.png")).string(), actual);
    return ::testing::AssertionFailure() << golden << " is " << expected.width << "x" << expected.height
                                         << ", the render " << actual.width << "x" << actual.height;
  }
  const DiffTolerance tolerance;
  const DiffStats stats = compare_images(expected, actual, tolerance.pixel_threshold);
  if (within_tolerance(stats, tolerance)) return ::testing::AssertionSuccess();
  fs::create_directories(out);
  const std::string actual_path = (out / (tag + "_actual.png")).string();
  const std::string diff_path = (out / (tag + "_diff.png")).string();
  write_png(actual_path, actual);
  write_png(diff_path, diff_image(expected, actual));
  return ::testing::AssertionFailure()
         << tag << " differs from " << golden << ": rms " << stats.rms << ", max " << stats.max << ", "
         << 100.0 * stats.over_fraction << "% of pixels past " << tolerance.pixel_threshold
         << "\n  actual: " << actual_path << "\n  diff:   " << diff_path
         << "\n  (if the change is intended: CLOTHSIM_UPDATE_GOLDEN=1 ctest -R Golden)";
}

class GoldenImage : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(GoldenImage, TheSceneRendersAsItsGoldenImage) {
  const GoldenCase& c = GetParam();
  const Image actual = renderer().render(scene_frame(c));
  const std::string golden = golden_path(c);
  if (updating_goldens()) {
    fs::create_directories(CLOTHSIM_GOLDEN_DIR);
    write_png(golden, actual, {{"scene", c.scene}, {"t", std::to_string(c.t)}});
    std::printf("updated %s\n", golden.c_str());
    return;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing: run the tests once with CLOTHSIM_UPDATE_GOLDEN=1";
  EXPECT_TRUE(matches_golden(golden, actual, c.scene));
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, GoldenImage, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<GoldenCase>& p) { return std::string(p.param.scene); });

// The tolerance separates noise from change, on the drape frame.
class GoldenTolerance : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    frame_ = new RenderFrame(scene_frame(kCases[0]));
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
