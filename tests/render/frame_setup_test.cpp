#include "frame_setup.h"

#include <gtest/gtest.h>

#include <string>

#include "renderer.h"
#include "render/synthetic_frames.h"

namespace clothsim::render {
namespace {

// Where a world point lands in normalised device coordinates.
Vec3 to_ndc(const Mat4& m, Vec3 p) {
  const float x = m.at(0, 0) * p.x + m.at(0, 1) * p.y + m.at(0, 2) * p.z + m.at(0, 3);
  const float y = m.at(1, 0) * p.x + m.at(1, 1) * p.y + m.at(1, 2) * p.z + m.at(1, 3);
  const float z = m.at(2, 0) * p.x + m.at(2, 1) * p.y + m.at(2, 2) * p.z + m.at(2, 3);
  const float w = m.at(3, 0) * p.x + m.at(3, 1) * p.y + m.at(3, 2) * p.z + m.at(3, 3);
  return {x / w, y / w, z / w};
}

TEST(FrameSetup, TheCameraTargetIsAtTheCentreOfTheImageAndUpIsUp) {
  RenderFrame frame;  // the course's camera: eye (0, 2, -10), target origin, fov 45
  const View v = make_view(frame);
  const Vec3 centre = to_ndc(v.view_proj, {0.f, 0.f, 0.f});
  EXPECT_NEAR(centre.x, 0.f, 1e-5f);
  EXPECT_NEAR(centre.y, 0.f, 1e-5f);
  EXPECT_GT(to_ndc(v.view_proj, {0.f, 1.f, 0.f}).y, 0.f);   // above the target: upper half
  // The camera looks along +z, so +x is on the viewer's left.
  EXPECT_LT(to_ndc(v.view_proj, {1.f, 0.f, 0.f}).x, 0.f);
  EXPECT_NEAR(v.distance, std::sqrt(104.f), 1e-4f);
}

TEST(FrameSetup, TheFieldOfViewIsVertical) {
  RenderFrame frame;
  frame.camera.eye = {0.f, 0.f, -10.f};
  const View v = make_view(frame);
  const float half = 10.f * std::tan(22.5f * 3.14159265f / 180.f);  // half the visible height at the target
  EXPECT_NEAR(to_ndc(v.view_proj, {0.f, half, 0.f}).y, 1.f, 1e-4f);
}

TEST(FrameSetup, TheKeyLightIsAboveAndOverTheViewersLeftShoulder) {
  for (auto eye : {std::array<float, 3>{0.f, 2.f, -10.f}, std::array<float, 3>{10.f, 3.f, 0.f},
                   std::array<float, 3>{0.f, 10.f, 0.001f}}) {
    RenderFrame frame;
    frame.camera.eye = eye;
    const View v = make_view(frame);
    EXPECT_NEAR(gl::length(v.light_dir), 1.f, 1e-5f);
    EXPECT_GT(v.light_dir.y, 0.7f);                      // mostly from above: shadows fall near
    EXPECT_LT(gl::dot(v.light_dir, v.right), 0.f);       // from the left
  }
}

TEST(FrameSetup, TheDrawnRegionHoldsTheClothSpheresAndShadowsWithAMargin) {
  RenderFrame frame = testing::draped_sheet_frame(320, 180, 5);
  const View v = make_view(frame);
  const PixelRect r = drawn_region(frame, v, 3);
  ASSERT_FALSE(r.empty());
  const auto inside = [&](Vec3 p) {
    const Vec3 ndc = to_ndc(v.view_proj, p);
    const float x = (ndc.x * 0.5f + 0.5f) * 320.f, y = (ndc.y * 0.5f + 0.5f) * 180.f;
    return x >= r.x0 + 3 && x <= r.x1 - 3 && y >= r.y0 + 3 && y <= r.y1 - 3;
  };
  for (std::size_t i = 0; i < frame.cloth_positions.size(); i += 3)
    EXPECT_TRUE(inside({frame.cloth_positions[i], frame.cloth_positions[i + 1], frame.cloth_positions[i + 2]}));
  EXPECT_TRUE(inside({0.f, -1.f, 0.f}));  // the bottom of the unit sphere
  // The sphere's shadow on the ground (y = -2), down the light ray from its centre.
  const float t = 2.f / v.light_dir.y;
  EXPECT_TRUE(inside({-v.light_dir.x * t, -2.f, -v.light_dir.z * t}));
  EXPECT_LT(r.width() * r.height(), 320 * 180);  // and it is not the whole image
}

TEST(FrameSetup, TheDrawnRegionIsEverythingWhenSomethingIsBehindTheCameraAndNothingWhenEmpty) {
  RenderFrame frame = testing::draped_sheet_frame(320, 180, 5);
  frame.spheres.push_back(RenderSphere{{0.f, 2.f, -12.f}, 0.5f, {1.f, 1.f, 1.f}});
  const PixelRect whole = drawn_region(frame, make_view(frame), 3);
  EXPECT_EQ(whole.x0, 0);
  EXPECT_EQ(whole.y0, 0);
  EXPECT_EQ(whole.x1, 320);
  EXPECT_EQ(whole.y1, 180);
  RenderFrame empty;
  EXPECT_TRUE(drawn_region(empty, make_view(empty), 3).empty());
}

TEST(FrameSetup, AValidFramePasses) {
  RenderFrame frame = testing::draped_sheet_frame(64, 36, 5);
  testing::add_grid_springs(frame, 5, 5);
  EXPECT_NO_THROW(validate_frame(frame, 4096));
}

TEST(FrameSetup, ValidationNamesWhatIsWrong) {
  const auto message = [](const RenderFrame& f) {
    try {
      validate_frame(f, 4096);
    } catch (const RenderError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  RenderFrame f = testing::draped_sheet_frame(64, 36, 5);
  f.width = 5000;
  EXPECT_EQ(message(f), "image size 5000x36 is outside 1..4096 pixels per side");
  f = testing::draped_sheet_frame(64, 36, 5);
  f.cloth_uv.resize(4);
  EXPECT_EQ(message(f), "RenderFrame: cloth_uv has 4 values, expected 50");
  f = testing::draped_sheet_frame(64, 36, 5);
  f.cloth_triangles.push_back(1);
  EXPECT_EQ(message(f), "RenderFrame: cloth_triangles is not a list of triangles");
  f = testing::draped_sheet_frame(64, 36, 5);
  f.spheres[0].radius = 0.f;
  EXPECT_NE(message(f).find("radius"), std::string::npos);
}

TEST(FrameSetup, OverlayTextScalesWithTheImageHeight) {
  // The same text covers 4x as many pixels at 720p (scale 2) as at 360p (scale 1).
  const auto inked = [](int w, int h) {
    Image image(w, h);
    for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = 128;
    RenderFrame frame;
    frame.overlay_lines = {"t = 1.000 s"};
    draw_overlay(image, frame);
    int n = 0;
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) n += image.rgba[i] == 255;
    return n;
  };
  EXPECT_EQ(inked(1280, 720), 4 * inked(640, 360));
}

}  // namespace
}  // namespace clothsim::render
