// The golden-image tolerance (imgdiff's defaults, which `clothsim golden check` and the
// project's golden images, tests/golden/manifest.yaml, use) checked both ways on the drape
// frame of the project's goldens: re-rendering passes it, and a real change to the picture
// (a sphere moved by 10 cm, another cloth colour, a missing shadow) fails it.
// The golden images of the shipped scenes are checked through `clothsim golden check`
// (tests/cli/golden/cmd_golden_test.cpp). One more, of what the renderer draws over a frame (a
// field-coloured cloth, its colour bar, the energy inset, overlay text at a 360-row tile's
// scale), is checked here from a frame built by hand: tests/golden/field_colour_bar_inset.png.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/run/simulation.h"
#include "render/image_diff.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "render/synthetic_frames.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "view/snapshot.h"

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
  RenderFrame frame = make_render_frame(model, run.state(), scene.render);
  // Overlay lines as `run` writes them (src/clip/frames/overlay_text.h), spelt out: render/ is
  // tested without the CLI's library.
  char lane[64], time[32];
  std::snprintf(lane, sizeof lane, "%s  dt = %.3g s", std::string(integrator_name(scene.integrator)).c_str(), scene.dt);
  std::snprintf(time, sizeof time, "t = %.3f s", run.state().t);
  frame.overlay_lines = {model.name, lane, time};
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

// The course's drape (closed form, synthetic_frames.h) at a 640x360 tile, coloured by an
// "error" growing from the sphere's top to the cloth's edge over four decades, with the bar,
// an energy inset half-way through its time axis, and two overlay lines.
RenderFrame field_golden_frame() {
  RenderFrame f = testing::draped_sheet_frame(640, 360, 25);
  for (std::size_t i = 0; i < f.cloth_positions.size(); i += 3) {
    const float r = std::hypot(f.cloth_positions[i], f.cloth_positions[i + 2]);  // 0 .. 2.83 m
    f.cloth_field.push_back(3e-6f * std::pow(10.f, 4.f * r / 2.83f));
  }
  testing::set_error_scale(f);
  f.overlay_lines = {"drape  rk4 @ 1e-3 s", "t = 1.500 s"};
  testing::show_energy_inset(f, 3.f, 30.f, 60.f);
  for (int i = 0; i <= 60; ++i) {  // up to t = 1.5 s: a damped wobble on a slow gain
    const float t = 0.025f * static_cast<float>(i);
    f.inset.t.push_back(t);
    f.inset.value.push_back(40.f + 6.f * t + 5.f * std::sin(8.f * t) * std::exp(-t));
  }
  return f;
}

bool updating_goldens() {
  const char* v = std::getenv("CLOTHSIM_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

TEST(FieldGolden, AFieldColouredFrameWithItsColourBarAndEnergyInsetMatchesItsGoldenImage) {
  const std::string golden = std::string(CLOTHSIM_GOLDEN_DIR) + "/field_colour_bar_inset.png";
  const Image actual = renderer().render(field_golden_frame());
  if (updating_goldens()) {
    write_png(golden, actual, {{"Source", "tests/render/golden_image_test.cpp field_golden_frame()"}}, 9);
    GTEST_SKIP() << "rewrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing (CLOTHSIM_UPDATE_GOLDEN=1 writes it)";
  const Image expected = read_png(golden);
  ASSERT_EQ(expected.width, actual.width);
  ASSERT_EQ(expected.height, actual.height);
  const DiffTolerance tolerance;
  const DiffStats stats = compare_images(expected, actual, tolerance.pixel_threshold);
  if (!within_tolerance(stats, tolerance)) {
    const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/field_colour_bar_inset";
    write_png(out + ".actual.png", actual);
    write_png(out + ".diff.png", diff_image(expected, actual));
    ADD_FAILURE() << "differs from " << golden << ": rms " << stats.rms << ", max " << stats.max << ", "
                  << 100 * stats.over_fraction << " % of pixels past " << tolerance.pixel_threshold
                  << "; see " << out << ".diff.png (if intended: CLOTHSIM_UPDATE_GOLDEN=1 ctest -R FieldGolden)";
  }
}

}  // namespace
}  // namespace clothsim
