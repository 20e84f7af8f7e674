#include "render/frame_setup.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "render/overlay_layout.h"
#include "render/renderer.h"
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

// Half the widest extent, in pixels, of points on the screen: a projected sphere's (an
// ellipse's) semi-major axis, found over directions a degree apart.
float half_widest_extent_px(const std::vector<std::array<float, 2>>& px) {
  float widest = 0.f;
  for (int deg = 0; deg < 180; ++deg) {
    const float c = std::cos(deg * 3.14159265f / 180.f), s = std::sin(deg * 3.14159265f / 180.f);
    float lo = 1e30f, hi = -1e30f;
    for (const auto& p : px) lo = std::min(lo, c * p[0] + s * p[1]), hi = std::max(hi, c * p[0] + s * p[1]);
    widest = std::max(widest, hi - lo);
  }
  return 0.5f * widest;
}

// Points spread over a sphere's surface (a Fibonacci lattice), each through `to_world`
// (identity, or down the key light onto the ground), projected to pixels.
std::vector<std::array<float, 2>> projected_sphere(const View& v, int width, int height, Vec3 c, float r,
                                                   const std::function<Vec3(Vec3)>& to_world) {
  std::vector<std::array<float, 2>> px;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const float y = 1.f - 2.f * (i + 0.5f) / n, ring = std::sqrt(1.f - y * y), a = 2.39996323f * i;
    const Vec3 ndc = to_ndc(v.view_proj, to_world(c + Vec3{ring * std::cos(a), y, ring * std::sin(a)} * r));
    px.push_back({(ndc.x * 0.5f + 0.5f) * width, (ndc.y * 0.5f + 0.5f) * height});
  }
  return px;
}

TEST(FrameSetup, ASpheresRadiusOnScreenIsItsOutlinesSemiMajorAxis) {
  const RenderFrame frame = testing::draped_sheet_frame(640, 360, 5);
  const View v = make_view(frame);
  const auto same = [](Vec3 p) { return p; };
  for (const Vec3 c : {Vec3{0.f, 0.f, 0.f}, Vec3{2.5f, 0.5f, -1.f}, Vec3{-3.f, -1.f, 2.f}}) {
    const float measured = half_widest_extent_px(projected_sphere(v, 640, 360, c, 0.6f, same));
    EXPECT_NEAR(sphere_radius_px(c, 0.6f, v, 360), measured, 0.01f * measured) << c.x << " " << c.y << " " << c.z;
  }
  // Twice the image height, twice the pixels.
  EXPECT_NEAR(sphere_radius_px({0.f, 0.f, 0.f}, 1.f, v, 720), 2.f * sphere_radius_px({0.f, 0.f, 0.f}, 1.f, v, 360), 1e-3f);
  // Holding the eye, or reaching the plane through it: unbounded.
  EXPECT_TRUE(std::isinf(sphere_radius_px(v.eye, 0.5f, v, 360)));
  EXPECT_TRUE(std::isinf(sphere_radius_px(v.eye + v.right * 1.f, 1.5f, v, 360)));
}

TEST(FrameSetup, ASpheresShadowOnScreenIsNoLargerThanItsMeasure) {
  const RenderFrame frame = testing::draped_sheet_frame(640, 360, 5);
  const View v = make_view(frame);
  const auto down_the_light = [&](Vec3 p) {  // as the shadow vertex shader
    const float drop = std::max(p.y - frame.ground_height, 0.f) / v.light_dir.y;
    return Vec3{p.x - v.light_dir.x * drop, frame.ground_height, p.z - v.light_dir.z * drop};
  };
  for (const Vec3 c : {Vec3{0.f, 0.f, 0.f}, Vec3{1.5f, 1.f, 1.f}}) {
    const float shadow = half_widest_extent_px(projected_sphere(v, 640, 360, c, 1.f, down_the_light));
    const float measure = sphere_shadow_radius_px(c, 1.f, frame.ground_height, v, 360);
    EXPECT_GE(measure, shadow);          // enough facets for the shadow's outline
    EXPECT_LE(measure, 2.5f * shadow);   // and not wildly more
  }
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
  // The same text covers 4x as many pixels at 720p (scale 4) as at 360p (scale 2).
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

// Rows holding white ink of an overlay line "H" drawn on a grey image of the given height:
// the cap height a viewer sees.
int measured_cap_height(int height) {
  Image image(height * 16 / 9, height);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = 128;
  RenderFrame frame;
  frame.overlay_lines = {"H"};
  draw_overlay(image, frame);
  int rows = 0;
  for (int y = 0; y < image.height; ++y) {
    bool ink = false;
    for (int x = 0; x < image.width && !ink; ++x) ink = image.pixel(x, y)[0] == 255;
    rows += ink;
  }
  return rows;
}

TEST(FrameSetup, OverlayCapHeightIsAtLeastTwelvePixelsAt360RowsAndAThirtiethOfTheHeightAtAnySize) {
  EXPECT_GE(measured_cap_height(360), 12);
  EXPECT_EQ(measured_cap_height(180), 7);
  EXPECT_EQ(measured_cap_height(358), 14);  // a 2x2 tile of a 1280x720 clip
  EXPECT_EQ(measured_cap_height(360), 14);
  EXPECT_EQ(measured_cap_height(720), 28);
  EXPECT_EQ(measured_cap_height(1080), 42);
  for (int h : {90, 180, 240, 300, 420, 540, 600, 900, 1440})
    EXPECT_GE(30 * measured_cap_height(h), h) << h << " rows";
}

RenderFrame field_frame() {
  RenderFrame f = testing::draped_sheet_frame(64, 36, 5);
  f.cloth_field.assign(25, 1e-3f);
  testing::set_error_scale(f);
  testing::show_energy_inset(f, 1.f, 0.f, 1.f);
  f.inset.t = {0.f, 0.5f};
  f.inset.value = {1.f, 2.f};
  return f;
}

std::string refusal(const RenderFrame& f) {
  try {
    validate_frame(f, 4096);
  } catch (const RenderError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(FrameSetup, AFieldAndAnInsetThatAgreeWithTheClothPass) {
  EXPECT_EQ(refusal(field_frame()), "(accepted)");
  RenderFrame linear = field_frame();
  linear.color_scale.log = false;
  linear.color_scale.lo = -1.f;  // below zero is fine on a linear scale
  EXPECT_EQ(refusal(linear), "(accepted)");
}

TEST(FrameSetup, AFieldOfTheWrongLengthOrABadScaleIsRefusedByName) {
  RenderFrame f = field_frame();
  f.cloth_field.resize(24);
  EXPECT_EQ(refusal(f), "RenderFrame: cloth_field has 24 values, expected 25 (one per particle) or none");
  f = field_frame();
  f.color_scale.lo = 1e-1f;
  f.color_scale.hi = 1e-3f;
  EXPECT_EQ(refusal(f), "RenderFrame: color_scale runs from 0.1 to 0.001: lo must be below hi, both finite");
  f = field_frame();
  f.color_scale.lo = 0.f;
  EXPECT_EQ(refusal(f), "RenderFrame: color_scale is logarithmic but lo is 0: both ends must be above 0");
  f = field_frame();
  f.color_scale.hi = std::numeric_limits<float>::infinity();
  EXPECT_NE(refusal(f).find("color_scale"), std::string::npos);
  // A scale is only checked when there is a field to colour by.
  f = field_frame();
  f.cloth_field.clear();
  f.color_scale.lo = 0.f;
  EXPECT_EQ(refusal(f), "(accepted)");
}

TEST(FrameSetup, AnInsetWithUnequalSeriesOrAnEmptyAxisIsRefusedByName) {
  RenderFrame f = field_frame();
  f.inset.value.push_back(3.f);
  EXPECT_EQ(refusal(f), "RenderFrame: inset has 2 times and 3 values");
  f = field_frame();
  f.inset.t_hi = f.inset.t_lo;
  EXPECT_EQ(refusal(f), "RenderFrame: inset time axis runs from 0 to 0: t_lo must be below t_hi");
  f = field_frame();
  f.inset.v_lo = 5.f;
  EXPECT_EQ(refusal(f), "RenderFrame: inset value axis runs from 5 to 1: v_lo must be below v_hi");
  f.inset.show = false;  // not drawn: not checked
  EXPECT_EQ(refusal(f), "(accepted)");
}

TEST(FrameSetup, TheBannerStaysLeftOfTheColourBarAndShrinksToFitThere) {
  RenderFrame f = field_frame();
  f.width = 640;
  f.height = 360;
  f.banner = {std::string(50, 'W')};  // 598 px at scale 2: wider than the room left of the bar
  Image image(640, 360);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = 128;
  draw_overlay(image, f);
  const OverlayLayout l = layout_overlay(f, 640, 360);
  ASSERT_FALSE(l.color_bar.empty());
  int red_in_panel = 0, red = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      if (p[0] != 255 || p[1] != 72 || p[2] != 60) continue;
      ++red;
      red_in_panel += x >= l.color_bar.x && x < l.color_bar.right() && y >= l.color_bar.y && y < l.color_bar.bottom();
    }
  EXPECT_GT(red, 0) << "the banner is drawn";
  EXPECT_EQ(red_in_panel, 0) << "no tick or label of the bar is hidden";
  EXPECT_LT(l.banner_scale, l.scale) << "shrunk to the room left of the bar";
  EXPECT_LE(l.banner.right(), l.color_bar.x);
  // A tile too narrow for the banner left of the bar, even at scale 1: across the picture,
  // over the bar, rather than cut.
  for (const auto& [w, h] : {std::pair{320, 360}, std::pair{256, 144}, std::pair{320, 240}}) {
    RenderFrame narrow = f;
    narrow.banner = {"DIVERGED", "at t = 0.0237 s", "(step 79)"};
    const OverlayLayout n = layout_overlay(narrow, w, h);
    EXPECT_GE(n.banner.x, 0) << w << "x" << h;
    EXPECT_LE(n.banner.right(), w) << w << "x" << h << ": not cut";
  }
  // Without a bar it is centred in the picture at the text scale (one text size in a picture).
  RenderFrame plain = f;
  plain.cloth_field.clear();
  plain.banner = {"DIVERGED"};
  const OverlayLayout p = layout_overlay(plain, 640, 360);
  EXPECT_EQ(p.banner_scale, p.scale);
  EXPECT_NEAR(p.banner.x + p.banner.w / 2, 320, p.banner_scale);
  EXPECT_NEAR(p.banner.y + p.banner.h / 2, 180, p.banner_scale);
}

TEST(FrameSetup, ADivergedBannerStaysInsideItsTileAtEveryWidth) {
  // "DIVERGED at t = 0.0237 s (step 79)" is 203 px at scale 1: it ran off the 158 px tiles of a
  // 320x180 compare. Drawn into a tile of each width, no red pixel lies in the margin or beyond.
  for (const auto& [w, h] : {std::pair{98, 58}, std::pair{104, 86}, std::pair{158, 88}, std::pair{200, 112},
                            std::pair{238, 134}, std::pair{320, 180}, std::pair{638, 358}}) {
    RenderFrame f;
    f.width = w;
    f.height = h;
    f.overlay_lines = {"t = 0.024 s", "79 force evals", "diverged: kinetic energy 7.63e+08 J exceeds the bound 4.08e+08 J"};
    f.banner = {"DIVERGED", "at t = 0.0237 s", "(step 79)"};
    Image image(w, h);
    for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = 128;
    draw_overlay(image, f);
    const OverlayLayout l = layout_overlay(f, w, h);
    int red = 0, first = w, last = -1;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::uint8_t* p = image.pixel(x, y);
        if (p[0] != 255 || p[1] != 72 || p[2] != 60) continue;
        ++red;
        first = std::min(first, x);
        last = std::max(last, x);
      }
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    EXPECT_GT(red, 0);
    EXPECT_GE(first, l.margin) << "inside the left margin";
    EXPECT_LT(last, w - l.margin) << "not run off the right edge";
    EXPECT_EQ(l.banner_lines.front().rfind("DIVERGED", 0), 0u);
  }
}

}  // namespace
}  // namespace clothsim::render
