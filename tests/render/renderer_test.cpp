#include "render/renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli/cli_process.h"
#include "render/colormap.h"
#include "render/frame_setup.h"
#include "render/image_diff.h"
#include "render/overlay_layout.h"
#include "render/synthetic_frames.h"

namespace clothsim {
namespace {

using testing::draped_sheet_frame;

// Small frames keep the suite fast; the renderer does not care about size.
constexpr int kW = 160, kH = 90;

Renderer& shared_renderer() {
  static Renderer renderer;  // one context for most tests: creating one costs ~50 ms
  return renderer;
}

// A red sphere alone, high above the camera's target: it can only be in the top half.
RenderFrame sphere_high_up_frame() {
  RenderFrame f;
  f.width = kW;
  f.height = kH;
  f.spheres.push_back(RenderSphere{{0.f, 2.4f, 0.f}, 0.8f, {1.f, 0.f, 0.f}});
  return f;
}

bool reddish(const std::uint8_t* p) { return p[0] > 120 && p[0] > p[1] + 60 && p[0] > p[2] + 60; }

int count_if_in_rows(const Image& image, int y0, int y1, bool (*pred)(const std::uint8_t*)) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < image.width; ++x) n += pred(image.pixel(x, y));
  return n;
}

// Mean of each channel over a centred box (side: a fifth of the image height).
std::array<double, 3> centre_mean(const Image& image) {
  const int r = image.height / 10;
  std::array<double, 3> sum{0, 0, 0};
  int n = 0;
  for (int y = image.height / 2 - r; y < image.height / 2 + r; ++y)
    for (int x = image.width / 2 - r; x < image.width / 2 + r; ++x, ++n)
      for (int c = 0; c < 3; ++c) sum[c] += image.pixel(x, y)[c];
  for (double& s : sum) s /= n;
  return sum;
}

int differing_pixels(const Image& a, const Image& b) {
  int n = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4)
    n += a.rgba[i] != b.rgba[i] || a.rgba[i + 1] != b.rgba[i + 1] || a.rgba[i + 2] != b.rgba[i + 2];
  return n;
}

TEST(Renderer, RunsOnAnOpenGl33CoreContextAndSaysWhichOne) {
  Renderer& r = shared_renderer();
  EXPECT_NE(r.gl_version().find("Core Profile"), std::string::npos) << r.gl_version();
  EXPECT_FALSE(r.gl_renderer().empty());
  EXPECT_GE(r.max_size(), 4096);
}

TEST(Renderer, WithoutAGl33CoreContextTheCommandFailsWithOneClearLine) {
  // Mesa's own override caps the version it offers: a machine without GL 3.3, simulated. Mesa
  // reads it once per process, so the renderer is exercised through the clothsim binary.
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/no_gl33.png";
  const auto r = testing::run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--duration",
                                        "0.01", "--still", "0", "--out", out},
                                       "env MESA_GL_VERSION_OVERRIDE=3.0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(testing::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("cannot create an OSMesa OpenGL 3.3 core context"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Renderer, ProducesAnOpaqueImageOfTheRequestedSize) {
  const Image image = shared_renderer().render(draped_sheet_frame(kW + 1, kH + 3));  // odd sizes
  ASSERT_EQ(image.width, kW + 1);
  ASSERT_EQ(image.height, kH + 3);
  ASSERT_EQ(image.rgba.size(), static_cast<std::size_t>(image.width) * image.height * 4);
  for (std::size_t i = 3; i < image.rgba.size(); i += 4) ASSERT_EQ(image.rgba[i], 255) << "pixel " << i / 4;
}

TEST(Renderer, TheSameFrameTwiceGivesIdenticalBytes) {
  Renderer& r = shared_renderer();
  RenderFrame frame = draped_sheet_frame(kW, kH);
  frame.overlay_lines = {"drape", "t = 1.000 s"};
  const Image first = r.render(frame);
  r.render(draped_sheet_frame(kW * 2, kH));  // a different size in between re-makes the FBOs
  const Image second = r.render(frame);
  EXPECT_EQ(first.rgba, second.rgba);
}

TEST(Renderer, DrawingOnlyWithinTheRegionOfTheGeometryChangesNoPixel) {
  // A sphere behind the camera is invisible but makes the drawn region the whole image.
  RenderFrame frame = draped_sheet_frame(kW, kH);
  frame.draw_particles = true;
  const Image limited = shared_renderer().render(frame);
  frame.spheres.push_back(RenderSphere{{0.f, 2.f, -20.f}, 0.5f, {0.f, 1.f, 0.f}});
  const Image whole = shared_renderer().render(frame);
  EXPECT_EQ(limited.rgba, whole.rgba);
}

TEST(Renderer, AFrameIsNotBlank) {
  const Image image = shared_renderer().render(draped_sheet_frame(kW, kH));
  std::set<std::uint32_t> colours;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    colours.insert(image.rgba[i] | image.rgba[i + 1] << 8 | image.rgba[i + 2] << 16);
  EXPECT_GT(colours.size(), 200u);  // shading, checker, grid, sky gradient
}

TEST(Renderer, IsNotUpsideDown) {
  const Image image = shared_renderer().render(sphere_high_up_frame());
  const int top = count_if_in_rows(image, 0, kH / 2, reddish);
  const int bottom = count_if_in_rows(image, kH / 2, kH, reddish);
  EXPECT_GT(top, 100);
  EXPECT_EQ(bottom, 0);
}

TEST(Renderer, TheClothShowsItsFrontColourFromAboveAndItsBackColourFromBelow) {
  RenderFrame frame = testing::flat_sheet_frame(kW, kH, 9);
  frame.has_ground = false;
  frame.cloth_front = {0.1f, 0.2f, 0.9f};  // blue
  frame.cloth_back = {0.9f, 0.5f, 0.1f};   // orange
  frame.camera.eye = {0.f, 6.f, -0.5f};     // above, looking down on the front (normals +y)
  const auto above = centre_mean(shared_renderer().render(frame));
  EXPECT_GT(above[2], above[0] + 40) << "expected blue from above";
  frame.camera.eye = {0.f, -6.f, -0.5f};    // below
  const auto below = centre_mean(shared_renderer().render(frame));
  EXPECT_GT(below[0], below[2] + 40) << "expected orange from below";
}

TEST(Renderer, TheCheckerPatternIsVisibleOnTheCloth) {
  RenderFrame frame = testing::flat_sheet_frame(kW * 2, kH * 2, 9);
  frame.has_ground = false;
  frame.camera.eye = {0.f, 6.f, -0.5f};
  const Image image = shared_renderer().render(frame);
  // Along the centre row, the brightness alternates between squares: many large jumps.
  int jumps = 0;
  const int y = image.height / 2;
  for (int x = image.width / 4; x < 3 * image.width / 4; ++x)
    jumps += std::abs(image.pixel(x + 1, y)[0] - image.pixel(x, y)[0]) > 25;
  EXPECT_GE(jumps, 3);
}

// A flat sheet seen from straight above, coloured by a field rising from 1e-6 at x = -2 m
// to 1e-1 at x = +2 m, on a log scale over exactly that range (so a decade per 0.8 m).
RenderFrame field_sheet_frame(int w, int h) {
  RenderFrame frame = testing::flat_sheet_frame(w, h, 17);
  frame.has_ground = false;
  frame.camera.eye = {0.f, 6.f, -0.5f};
  for (std::size_t i = 0; i < frame.cloth_positions.size(); i += 3)
    frame.cloth_field.push_back(std::pow(10.f, -6.f + 5.f * (frame.cloth_positions[i] + 2.f) / 4.f));
  testing::set_error_scale(frame);
  frame.color_scale.show_bar = false;
  return frame;
}

// The pixel where a world point lands.
const std::uint8_t* pixel_at(const Image& image, const RenderFrame& frame, gl::Vec3 p) {
  const gl::Mat4 m = render::make_view(frame).view_proj;
  const float w = m.at(3, 0) * p.x + m.at(3, 1) * p.y + m.at(3, 2) * p.z + m.at(3, 3);
  const float x = (m.at(0, 0) * p.x + m.at(0, 1) * p.y + m.at(0, 2) * p.z + m.at(0, 3)) / w;
  const float y = (m.at(1, 0) * p.x + m.at(1, 1) * p.y + m.at(1, 2) * p.z + m.at(1, 3)) / w;
  return image.pixel(static_cast<int>((x * 0.5f + 0.5f) * image.width), static_cast<int>((0.5f - y * 0.5f) * image.height));
}

TEST(Renderer, AFieldColoursTheClothPurpleWhereLowTealInBetweenAndYellowWhereHigh) {
  const RenderFrame frame = field_sheet_frame(kW * 2, kH * 2);
  const Image image = shared_renderer().render(frame);
  const std::uint8_t* low = pixel_at(image, frame, {-1.6f, 0.f, 0.f});   // 1e-5.5
  const std::uint8_t* mid = pixel_at(image, frame, {0.f, 0.f, 0.f});     // 1e-3.5
  const std::uint8_t* high = pixel_at(image, frame, {1.6f, 0.f, 0.f});   // 1e-1.5
  EXPECT_GT(low[2], low[1] + 40) << "viridis' low end: dark purple, blue over green";
  EXPECT_GT(low[0], low[1] + 20);
  EXPECT_GT(mid[1], mid[0] + 40) << "the middle: teal, green over red";
  EXPECT_GT(high[0], high[2] + 80) << "the high end: yellow, red and green over blue";
  EXPECT_GT(high[1], high[2] + 80);
  EXPECT_GT(high[1] + high[0], low[1] + low[0] + 200) << "and much lighter";
  // No checker: along a line of constant field the colour does not alternate.
  int jumps = 0;
  for (float z = -1.5f; z < 1.5f; z += 0.05f)
    jumps += std::abs(pixel_at(image, frame, {0.f, 0.f, z})[1] - pixel_at(image, frame, {0.f, 0.f, z + 0.05f})[1]) > 25;
  EXPECT_EQ(jumps, 0);
}

TEST(Renderer, BothFacesOfTheClothShowTheFieldColour) {
  RenderFrame frame = field_sheet_frame(kW, kH);
  frame.cloth_field.assign(frame.cloth_field.size(), 1e-7f);  // below lo: the low end, dark purple
  frame.cloth_back = {0.9f, 0.5f, 0.1f};                      // orange, if the back were used
  frame.camera.eye = {0.f, -6.f, -0.5f};                      // from below: the back face
  const auto below = centre_mean(shared_renderer().render(frame));
  EXPECT_GT(below[2], below[1] + 15) << "purple, not orange";
}

TEST(Renderer, AFieldFrameCarriesItsColourBarAtTheRightEdge) {
  RenderFrame frame = field_sheet_frame(320, 180);
  frame.color_scale.show_bar = true;
  const Image image = shared_renderer().render(frame);
  const render::OverlayLayout l = render::layout_overlay(frame, 320, 180);
  ASSERT_FALSE(l.bar.empty());
  const auto top = render::colormap_rgb8(1.f - 0.5f / static_cast<float>(l.bar.h));
  const std::uint8_t* p = image.pixel(l.bar.x + l.bar.w / 2, l.bar.y);
  EXPECT_EQ((std::array<std::uint8_t, 3>{p[0], p[1], p[2]}), top) << "drawn after read-back: exact bytes";
}

TEST(Renderer, EmptyFieldAndAHiddenInsetLeaveTheFrameAsBefore) {
  RenderFrame frame = draped_sheet_frame(kW, kH);
  frame.overlay_lines = {"drape"};
  const Image plain = shared_renderer().render(frame);
  frame.color_scale.label = "strain";
  frame.inset.t = {0.f, 1.f};
  frame.inset.value = {1.f, 2.f};
  frame.inset.label = "total energy [J]";
  EXPECT_EQ(shared_renderer().render(frame).rgba, plain.rgba);
}

TEST(Renderer, SpheresCastAShadowOnTheGroundBelowThem) {
  RenderFrame frame = sphere_high_up_frame();
  frame.spheres[0].center = {0.f, -0.5f, 0.f};
  frame.has_ground = true;
  frame.ground_height = -2.f;
  const Image lit = shared_renderer().render([&] { RenderFrame f = frame; f.shadows = false; return f; }());
  const Image shadowed = shared_renderer().render(frame);
  int darker = 0, lighter = 0;
  for (std::size_t i = 0; i < lit.rgba.size(); i += 4) {
    darker += shadowed.rgba[i + 1] + 20 < lit.rgba[i + 1];
    lighter += shadowed.rgba[i + 1] > lit.rgba[i + 1] + 2;
  }
  EXPECT_GT(darker, 50);   // a shadow of some size...
  EXPECT_EQ(lighter, 0);   // ... that only darkens
}

TEST(Renderer, WithoutGroundTheBackdropStillHasAGradient) {
  RenderFrame frame;
  frame.width = kW;
  frame.height = kH;
  const Image image = shared_renderer().render(frame);
  const std::uint8_t* top = image.pixel(kW / 2, 0);
  const std::uint8_t* bottom = image.pixel(kW / 2, kH - 1);
  EXPECT_NE(top[0] + top[1] + top[2], bottom[0] + bottom[1] + bottom[2]);
}

TEST(Renderer, SpringLinesAndParticlesAreDrawnWhenAsked) {
  RenderFrame frame = draped_sheet_frame(kW, kH, 9);
  const Image plain = shared_renderer().render(frame);
  testing::add_grid_springs(frame, 9, 9);
  const Image springs = shared_renderer().render(frame);
  frame.draw_particles = true;
  const Image particles = shared_renderer().render(frame);
  EXPECT_GT(differing_pixels(plain, springs), 100);
  EXPECT_GT(differing_pixels(springs, particles), 20);
}

TEST(Renderer, AClothWithoutTrianglesShowsItsParticlesAsBallsJoinedByLines) {
  // A single spring, as scenes/spring.yaml: two particles, one line, no surface.
  RenderFrame frame;
  frame.width = kW * 2;
  frame.height = kH * 2;
  frame.cloth_positions = {-1.f, 0.f, 0.f, 1.f, 0.f, 0.f};
  frame.cloth_normals = {0.f, 1.f, 0.f, 0.f, 1.f, 0.f};
  frame.cloth_uv = {0.f, 0.f, 1.f, 0.f};
  frame.spring_lines = {0, 1};
  frame.spring_types = {0};
  const Image background = shared_renderer().render([&] { RenderFrame f = frame; f.spring_lines.clear(); f.spring_types.clear(); return f; }());
  const Image line = shared_renderer().render(frame);
  frame.draw_particles = true;
  const Image balls = shared_renderer().render(frame);
  EXPECT_GT(differing_pixels(background, line), 60);    // ~43 px long at 180 rows, 2 px wide
  EXPECT_GT(differing_pixels(line, balls), 2 * 30);     // two balls of several pixels each
}

TEST(Renderer, TheBannerIsRedAndCentred) {
  RenderFrame frame = draped_sheet_frame(kW * 2, kH * 2);
  frame.spheres.clear();
  const Image without = shared_renderer().render(frame);
  frame.banner = {"DIVERGED", "at t = 1.234 s"};
  const Image with = shared_renderer().render(frame);
  const auto bright_red = [](const std::uint8_t* p) { return p[0] > 200 && p[1] < 120 && p[2] < 120; };
  int centre = 0, elsewhere = 0;
  for (int y = 0; y < with.height; ++y)
    for (int x = 0; x < with.width; ++x) {
      if (!bright_red(with.pixel(x, y)) || bright_red(without.pixel(x, y))) continue;
      (std::abs(y - with.height / 2) < with.height / 6 ? centre : elsewhere) += 1;
    }
  EXPECT_GT(centre, 100);
  EXPECT_EQ(elsewhere, 0);
}

TEST(Renderer, OverlayLinesAreDrawnTopLeft) {
  RenderFrame frame = draped_sheet_frame(kW * 2, kH * 2);
  const Image without = shared_renderer().render(frame);
  frame.overlay_lines = {"drape", "symplectic_euler", "t = 0.000 s"};
  const Image with = shared_renderer().render(frame);
  int changed_top_left = 0, changed_elsewhere = 0;
  for (int y = 0; y < with.height; ++y)
    for (int x = 0; x < with.width; ++x) {
      const bool changed = std::memcmp(with.pixel(x, y), without.pixel(x, y), 3) != 0;
      (x < with.width / 2 && y < with.height / 3 ? changed_top_left : changed_elsewhere) += changed;
    }
  EXPECT_GT(changed_top_left, 500);
  EXPECT_EQ(changed_elsewhere, 0);
}

TEST(Renderer, MultisamplingSmoothsEdgesAndOneSampleAlsoWorks) {
  RenderFrame frame = sphere_high_up_frame();
  frame.samples = 1;
  const Image aliased = shared_renderer().render(frame);
  frame.samples = 4;
  const Image smooth = shared_renderer().render(frame);
  frame.samples = 64;  // above GL_MAX_SAMPLES: clamped, not an error
  EXPECT_EQ(shared_renderer().render(frame).rgba, smooth.rgba);
  // Edge pixels of the sphere: only the multisampled image has colours between red and sky.
  EXPECT_GT(differing_pixels(aliased, smooth), 10);
}

TEST(Renderer, FxaaBringsAOneSampleFrameCloseToTheMultisampledOne) {
  RenderFrame frame = draped_sheet_frame(kW * 4, kH * 4);
  frame.samples = 4;
  const Image msaa = shared_renderer().render(frame);
  frame.samples = 1;
  const Image aliased = shared_renderer().render(frame);
  frame.fxaa = true;
  const Image smoothed = shared_renderer().render(frame);
  const DiffStats before = compare_images(aliased, msaa, 0), after = compare_images(smoothed, msaa, 0);
  EXPECT_LT(after.rms, 0.9 * before.rms) << "RMS against 4x MSAA " << before.rms << " -> " << after.rms;
  // Under FXAA the backdrop is drawn with 4 samples all the same: the rows above the cloth,
  // where only the sky and the ground's far grid show, are the multisampled frame's.
  const render::View view = render::make_view(frame);
  // Widened as the renderer widens it at 360 rows (4 + 4 px, renderer.cpp): outside, only the backdrop.
  const render::PixelRect region = render::drawn_region(frame, view, 8);
  const int top_rows = frame.height - region.y1;  // GL rows are bottom-up
  ASSERT_GT(top_rows, 10);
  for (int y = 0; y < top_rows; ++y)
    ASSERT_EQ(std::memcmp(smoothed.pixel(0, y), msaa.pixel(0, y), 4 * static_cast<std::size_t>(frame.width)), 0)
        << "row " << y;
  // And rendering without FXAA again gives the aliased frame back (targets switch samples).
  frame.fxaa = false;
  EXPECT_EQ(shared_renderer().render(frame).rgba, aliased.rgba);
}

TEST(Renderer, RefusesASizeOfZeroOrAboveTheGlLimit) {
  Renderer& r = shared_renderer();
  for (auto [w, h] : {std::pair{0, 90}, std::pair{160, 0}, std::pair{-4, 90},
                      std::pair{r.max_size() + 1, 90}, std::pair{160, r.max_size() + 1}}) {
    RenderFrame frame = draped_sheet_frame(kW, kH);
    frame.width = w;
    frame.height = h;
    try {
      r.render(frame);
      ADD_FAILURE() << "accepted " << w << "x" << h;
    } catch (const RenderError& e) {
      EXPECT_NE(std::string(e.what()).find("outside 1.."), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(r.render(draped_sheet_frame(kW, kH)).width, kW);  // still usable afterwards
}

TEST(Renderer, RefusesAFrameWhoseArraysDisagree) {
  Renderer& r = shared_renderer();
  RenderFrame bad_normals = draped_sheet_frame(kW, kH, 5);
  bad_normals.cloth_normals.pop_back();
  EXPECT_THROW(r.render(bad_normals), RenderError);
  RenderFrame bad_index = draped_sheet_frame(kW, kH, 5);
  bad_index.cloth_triangles[7] = 25;  // 5 x 5 particles: 0..24
  EXPECT_THROW(r.render(bad_index), RenderError);
  RenderFrame bad_springs = draped_sheet_frame(kW, kH, 5);
  testing::add_grid_springs(bad_springs, 5, 5);
  bad_springs.spring_types.pop_back();
  EXPECT_THROW(r.render(bad_springs), RenderError);
}

TEST(Renderer, SeveralRenderersWorkSideBySideOnOneThreadAndOnSeveral) {
  const RenderFrame a = draped_sheet_frame(kW, kH);
  const RenderFrame b = sphere_high_up_frame();
  const Image expected_a = shared_renderer().render(a);
  const Image expected_b = shared_renderer().render(b);

  Renderer first, second;  // interleaved on this thread: each makes its own context current
  EXPECT_EQ(first.render(a).rgba, expected_a.rgba);
  EXPECT_EQ(second.render(b).rgba, expected_b.rgba);
  EXPECT_EQ(first.render(b).rgba, expected_b.rgba);

  Image from_thread_a, from_thread_b;  // concurrently, as `clothsim compare` may
  std::thread ta([&] { for (int i = 0; i < 3; ++i) from_thread_a = first.render(a); });
  std::thread tb([&] { for (int i = 0; i < 3; ++i) from_thread_b = second.render(b); });
  ta.join();
  tb.join();
  EXPECT_EQ(from_thread_a.rgba, expected_a.rgba);
  EXPECT_EQ(from_thread_b.rgba, expected_b.rgba);
}

TEST(Renderer, RenderersMadeAndDestroyedInsideConcurrentThreadsAgree) {
  const RenderFrame frame = draped_sheet_frame(kW, kH);
  const Image expected = shared_renderer().render(frame);
  std::array<Image, 3> results;
  std::vector<std::thread> threads;
  for (Image& result : results)
    threads.emplace_back([&frame, &result] {
      Renderer own;  // context created, used and destroyed on this thread
      own.render(frame);
      result = own.render(frame);
    });
  for (std::thread& t : threads) t.join();
  for (const Image& result : results) EXPECT_EQ(result.rgba, expected.rgba);
}

}  // namespace
}  // namespace clothsim
