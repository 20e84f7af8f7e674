#include "render/series_inset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "render/synthetic_frames.h"

namespace clothsim::render {
namespace {

using testing::grey_image;

bool amber(const std::uint8_t* p) { return p[0] == 255 && p[1] == 204 && p[2] == 64; }

// Energy rising linearly from 0 to 10 J over the first 2 s of a 4 s axis.
RenderFrame inset_frame(int w, int h) {
  RenderFrame f;
  f.width = w;
  f.height = h;
  testing::show_energy_inset(f, 4.f, 0.f, 20.f);
  for (int i = 0; i <= 40; ++i) {
    f.inset.t.push_back(0.05f * static_cast<float>(i));
    f.inset.value.push_back(0.25f * static_cast<float>(i));
  }
  return f;
}

// The topmost curve pixel in column x of the plot, or -1.
int curve_row(const Image& image, const ImageBox& plot, int x) {
  for (int y = plot.y; y < plot.bottom(); ++y)
    if (amber(image.pixel(x, y))) return y;
  return -1;
}

TEST(SeriesInset, DrawsInTheBottomRightCornerOnlyAndItsCurveRisesWithTheValues) {
  const RenderFrame f = inset_frame(640, 360);
  const OverlayLayout l = layout_overlay(f, 640, 360);
  Image image = grey_image(640, 360);
  draw_series_inset(image, f.inset, l);
  int outside = 0, curve = 0;
  for (int y = 0; y < 360; ++y)
    for (int x = 0; x < 640; ++x) {
      if (!l.inset.contains(x, y)) outside += image.pixel(x, y)[0] != 128;
      curve += amber(image.pixel(x, y));
    }
  EXPECT_EQ(outside, 0);
  EXPECT_GT(curve, 30);
  EXPECT_GT(l.inset.x, 640 / 2);
  EXPECT_GT(l.inset.y, 360 / 2);
  // t = 0.5 s sits an eighth of the way along the axis, t = 1.5 s three eighths: the later is higher.
  const int early = curve_row(image, l.plot, l.plot.x + l.plot.w / 8);
  const int later = curve_row(image, l.plot, l.plot.x + 3 * l.plot.w / 8);
  ASSERT_GE(early, 0);
  ASSERT_GE(later, 0);
  EXPECT_LT(later, early);
  // Past the last sample (t = 2 s, half the axis) nothing is drawn yet.
  EXPECT_EQ(curve_row(image, l.plot, l.plot.x + 3 * l.plot.w / 4), -1);
}

TEST(SeriesInset, ValuesPastTheAxisLieOnItsEdgeAndNonFiniteOnesBreakTheCurve) {
  RenderFrame f = inset_frame(640, 360);
  for (std::size_t i = 10; i < 20; ++i) f.inset.value[i] = 1e30f;                                    // far above v_hi
  for (std::size_t i = 25; i < 35; ++i) f.inset.value[i] = std::numeric_limits<float>::quiet_NaN();  // diverged
  const OverlayLayout l = layout_overlay(f, 640, 360);
  Image image = grey_image(640, 360);
  draw_series_inset(image, f.inset, l);
  const auto column = [&](float t) {
    return l.plot.x + std::max(1, l.scale / 2) + static_cast<int>(std::lround(t / 4.f * static_cast<float>(l.plot.w - 2)));
  };
  const int top = curve_row(image, l.plot, column(0.7f));
  EXPECT_GE(top, l.plot.y);
  EXPECT_LE(top, l.plot.y + 1) << "clamped to the top of the graph";
  EXPECT_EQ(curve_row(image, l.plot, column(1.5f)), -1) << "a gap where the values are not finite";
}

TEST(SeriesInset, NothingIsDrawnWhenNotShown) {
  RenderFrame f = inset_frame(320, 180);
  f.inset.show = false;
  Image image = grey_image(320, 180);
  const Image before = image;
  draw_series_inset(image, f.inset, layout_overlay(f, 320, 180));
  EXPECT_EQ(image.rgba, before.rgba);
}

}  // namespace
}  // namespace clothsim::render
