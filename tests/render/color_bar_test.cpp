#include "render/color_bar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "render/colormap.h"
#include "render/synthetic_frames.h"
#include "render/text.h"

namespace clothsim::render {
namespace {

using testing::grey_image;

RenderFrame field_frame(int w, int h) {
  RenderFrame f;
  f.width = w;
  f.height = h;
  f.cloth_positions.assign(6, 0.f);
  f.cloth_field = {1e-5f, 1e-2f};
  testing::set_error_scale(f);
  return f;
}

bool same(const std::uint8_t* p, std::array<std::uint8_t, 3> c) { return p[0] == c[0] && p[1] == c[1] && p[2] == c[2]; }
bool white(const std::uint8_t* p) { return p[0] == 255 && p[1] == 255 && p[2] == 255; }

int white_pixels(const Image& image, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = std::max(y0, 0); y < std::min(y1, image.height); ++y)
    for (int x = std::max(x0, 0); x < std::min(x1, image.width); ++x) n += white(image.pixel(x, y));
  return n;
}

TEST(ColorBar, TheGradientRunsFromTheHighColourAtTheTopToTheLowAtTheBottomOfItsBox) {
  const RenderFrame f = field_frame(640, 360);
  const OverlayLayout l = layout_overlay(f, 640, 360);
  Image image = grey_image(640, 360);
  draw_color_bar(image, f.color_scale, l);
  const int x = l.bar.x + l.bar.w / 2;
  EXPECT_TRUE(same(image.pixel(x, l.bar.y), colormap_rgb8(1.f - 0.5f / static_cast<float>(l.bar.h))));
  EXPECT_TRUE(same(image.pixel(x, l.bar.bottom() - 1), colormap_rgb8(0.5f / static_cast<float>(l.bar.h))));
  const int middle = l.bar.y + l.bar.h / 2;
  EXPECT_TRUE(same(image.pixel(x, middle), colormap_rgb8(1.f - (static_cast<float>(l.bar.h / 2) + 0.5f) / static_cast<float>(l.bar.h))));
  // At the right edge of the image, in its upper half.
  EXPECT_GT(l.bar.x, 640 * 3 / 4);
  EXPECT_LT(l.bar.y, 360 / 4);
}

TEST(ColorBar, EveryTickHasALabelBesideItAndTheTitleIsWrittenAboveTheBar) {
  const RenderFrame f = field_frame(640, 360);
  const OverlayLayout l = layout_overlay(f, 640, 360);
  Image image = grey_image(640, 360);
  draw_color_bar(image, f.color_scale, l);
  ASSERT_EQ(l.ticks.size(), 6u);  // 1e-6 .. 1e-1
  for (const ScaleTick& tick : l.ticks) {
    const int y = l.bar.y + static_cast<int>(std::lround((1.f - tick.position) * static_cast<float>(l.bar.h - 1)));
    // Glyph ink in the label's band, left of the tick mark: "1e-4" has ink in every row band.
    EXPECT_GT(white_pixels(image, l.color_bar.x, y - 4 * l.scale, l.bar.x - 2 * l.scale - 1, y + 4 * l.scale), 20)
        << tick.text;
  }
  EXPECT_GT(white_pixels(image, l.color_bar.x, l.title_y, l.color_bar.right(), l.title_y + 7 * l.scale),
            text_width("error [m]", l.scale)) << "the title";
}

TEST(ColorBar, DrawsOnlyInsideItsPanel) {
  const RenderFrame f = field_frame(320, 180);
  const OverlayLayout l = layout_overlay(f, 320, 180);
  Image image = grey_image(320, 180);
  draw_color_bar(image, f.color_scale, l);
  int outside = 0;
  for (int y = 0; y < 180; ++y)
    for (int x = 0; x < 320; ++x) outside += !l.color_bar.contains(x, y) && image.pixel(x, y)[0] != 128;
  EXPECT_EQ(outside, 0);
  // The panel is darkened behind the labels so they read on a light sky.
  EXPECT_LT(image.pixel(l.color_bar.x + 1, l.color_bar.y + 1)[0], 128);
}

TEST(ColorBar, NothingIsDrawnWithoutAField) {
  RenderFrame f = field_frame(320, 180);
  f.cloth_field.clear();
  Image image = grey_image(320, 180);
  const Image before = image;
  draw_color_bar(image, f.color_scale, layout_overlay(f, 320, 180));
  EXPECT_EQ(image.rgba, before.rgba);
}

TEST(ColorBar, AGridsStripHoldsTheWholeLegendAndDrawsNothingOutsideIt) {
  // The widest title compare draws and the widest ticks (a range under two decades: "1.5e-5").
  for (const auto& [label, lo, hi] : {std::tuple{"speed [m/s]", 1.5e-5f, 7.5e-5f}, std::tuple{"error [m]", 1e-6f, 1e-1f}})
    for (int s : {1, 2, 4}) {
      ColorScale scale;
      scale.label = label;
      scale.lo = lo;
      scale.hi = hi;
      const int w = color_bar_strip_width(label, s), h = 120 * s;
      const ImageBox strip{200, 0, w, h};
      Image image = grey_image(200 + w + 10, h);
      draw_color_bar_strip(image, scale, strip, s);
      const OverlayLayout l = layout_color_bar_strip(scale, strip, s);
      int outside = 0;
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) outside += !strip.contains(x, y) && image.pixel(x, y)[0] != 128;
      EXPECT_EQ(outside, 0) << label << " at scale " << s;
      // Every tick label inside the panel (none cut at its left edge), the bar half the strip high.
      for (const ScaleTick& tick : l.ticks)
        EXPECT_GE(l.bar.x - 1 - 3 * s - text_width(tick.text, s), l.color_bar.x) << tick.text;
      EXPECT_GE(l.color_bar.x, strip.x);
      EXPECT_EQ(l.bar.h, h / 2);
      EXPECT_TRUE(same(image.pixel(l.bar.x + 1, l.bar.y), colormap_rgb8(1.f - 0.5f / static_cast<float>(l.bar.h))));
    }
}

}  // namespace
}  // namespace clothsim::render
