#include "render/fxaa.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace clothsim {
namespace {

constexpr int kW = 96, kH = 64;
constexpr std::uint8_t kDark = 30, kLight = 220;

// A dark half-plane below the line y = y0 + slope x (rows top-down) on a light ground, drawn
// as a rasterizer with one sample per pixel draws it: a pixel is dark when its centre is.
Image staircase(double slope, double y0) {
  Image image(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool dark = y + 0.5 > y0 + slope * (x + 0.5);
      std::uint8_t* p = image.pixel(x, y);
      p[0] = p[1] = p[2] = dark ? kDark : kLight;
      p[3] = 255;
    }
  return image;
}

// The same half-plane with each pixel's exact coverage (16 x 16 samples): what antialiasing
// approaches.
std::vector<double> exact_shades(double slope, double y0) {
  std::vector<double> out(static_cast<std::size_t>(kW) * kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      int covered = 0;
      for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) covered += y + (j + 0.5) / 16 > y0 + slope * (x + (i + 0.5) / 16);
      const double c = covered / 256.0;
      out[static_cast<std::size_t>(y) * kW + x] = c * kDark + (1 - c) * kLight;
    }
  return out;
}

// RMS of the red channel against the exact shades, over the columns away from the image's
// left and right borders (where the edge's ends are cut off).
double rms_error(const Image& image, const std::vector<double>& exact) {
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 8; x < kW - 8; ++x, ++n) {
      const double d = image.pixel(x, y)[0] - exact[static_cast<std::size_t>(y) * kW + x];
      sum += d * d;
    }
  return std::sqrt(sum / n);
}

TEST(Fxaa, TurnsTheStaircaseOfANearlyHorizontalEdgeIntoARamp) {
  for (double slope : {0.1, 0.25, -0.2}) {
    const double y0 = slope > 0 ? 20.3 : 44.3;
    Image image = staircase(slope, y0);
    const std::vector<double> exact = exact_shades(slope, y0);
    const double before = rms_error(image, exact);
    fxaa(image, 0, 0, kW, kH, nullptr);
    const double after = rms_error(image, exact);
    EXPECT_LT(after, 0.6 * before) << "slope " << slope << ": RMS " << before << " -> " << after;
  }
}

TEST(Fxaa, TurnsTheStaircaseOfANearlyVerticalEdgeIntoARampAsWell) {
  // The same edge transposed: the search runs down the columns.
  const double slope = 0.2, y0 = 20.3;
  Image wide = staircase(slope, y0);
  const std::vector<double> exact_wide = exact_shades(slope, y0);
  Image image(kH, kW);
  std::vector<double> exact(exact_wide.size());
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      std::copy_n(wide.pixel(x, y), 4, image.pixel(y, x));
      exact[static_cast<std::size_t>(x) * kH + y] = exact_wide[static_cast<std::size_t>(y) * kW + x];
    }
  double before = 0.0, after = 0.0;
  const auto rms = [&](const Image& im) {
    double sum = 0.0;
    int n = 0;
    for (int y = 8; y < kW - 8; ++y)
      for (int x = 0; x < kH; ++x, ++n) {
        const double d = im.pixel(x, y)[0] - exact[static_cast<std::size_t>(y) * kH + x];
        sum += d * d;
      }
    return std::sqrt(sum / n);
  };
  before = rms(image);
  fxaa(image, 0, 0, kH, kW, nullptr);
  after = rms(image);
  EXPECT_LT(after, 0.6 * before) << "RMS " << before << " -> " << after;
}

TEST(Fxaa, LeavesFlatAndFaintlyShadedPicturesAlone) {
  Image image(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      // A gentle gradient and a step of 5 of 255: below both contrast thresholds.
      p[0] = p[1] = p[2] = static_cast<std::uint8_t>(100 + x / 8 + (y > kH / 2 ? 5 : 0));
      p[3] = 255;
    }
  const Image before = image;
  fxaa(image, 0, 0, kW, kH, nullptr);
  EXPECT_EQ(image.rgba, before.rgba);
}

TEST(Fxaa, AStraightEdgeOnAPixelBoundaryMovesByTheSubpixelTermAtMost) {
  // No staircase to mend: only FXAA's sub-pixel term touches it, by under 6 % of the step.
  Image image = staircase(0.0, 32.0);
  const Image before = image;
  fxaa(image, 0, 0, kW, kH, nullptr);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      EXPECT_LE(std::abs(image.pixel(x, y)[0] - before.pixel(x, y)[0]), 0.06 * (kLight - kDark))
          << "at " << x << ", " << y;
}

TEST(Fxaa, TouchesOnlyTheRectangleAndThePixelsNextToWhatWasDrawn) {
  const double slope = 0.25, y0 = 20.3;
  const Image original = staircase(slope, y0);
  // Drawn: the left half of the rectangle [8, 88) x [4, 60); the staircase crosses both halves.
  const int x0 = 8, y0r = 4, x1 = 88, y1 = 60, w = x1 - x0, h = y1 - y0r;
  std::vector<std::uint8_t> drawn(static_cast<std::size_t>(w) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 2; ++x) drawn[static_cast<std::size_t>(y) * w + x] = 255;
  Image image = original;
  fxaa(image, x0, y0r, x1, y1, drawn.data());
  int changed_inside = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool changed = image.pixel(x, y)[0] != original.pixel(x, y)[0];
      const bool considered = x >= x0 && x <= x0 + w / 2 && y >= y0r && y < y1;  // drawn, or its neighbour
      if (considered) changed_inside += changed;
      else EXPECT_FALSE(changed) << "at " << x << ", " << y;
    }
  EXPECT_GT(changed_inside, 20);
}

TEST(Fxaa, EachPixelIsBlendedFromThePictureAsItWasSoTheResultIsTheSameTwice) {
  Image a = staircase(0.3, 10.7), b = a;
  fxaa(a, 0, 0, kW, kH, nullptr);
  fxaa(b, 0, 0, kW, kH, nullptr);
  EXPECT_EQ(a.rgba, b.rgba);
  // A rectangle reaching past the image is clipped to it, and a mask given over that rectangle
  // is read where the clipped part lies in it.
  Image c = staircase(0.3, 10.7);
  fxaa(c, -5, -5, kW + 5, kH + 5, nullptr);
  EXPECT_EQ(c.rgba, a.rgba);
  const int mw = kW + 10, mh = kH + 10;
  std::vector<std::uint8_t> all(static_cast<std::size_t>(mw) * mh, 255);
  Image d = staircase(0.3, 10.7);
  fxaa(d, -5, -5, kW + 5, kH + 5, all.data());
  EXPECT_EQ(d.rgba, a.rgba) << "a mask drawn everywhere considers every pixel";
  std::vector<std::uint8_t> none_but_border(static_cast<std::size_t>(mw) * mh, 0);
  for (int x = 0; x < mw; ++x) none_but_border[x] = 255;  // the mask's first row lies outside the image
  Image e = staircase(0.3, 10.7);
  const Image original = e;
  fxaa(e, -5, -5, kW + 5, kH + 5, none_but_border.data());
  EXPECT_EQ(e.rgba, original.rgba) << "only mask rows outside the image are set: nothing to do";
}

TEST(Fxaa, EachBlendMixesAPixelWithOneOfItsOriginalNeighbours) {
  // A one-pixel dark line at a shallow slope: blending in place would let a blended pixel feed
  // its neighbour's blend. Every changed pixel must lie between its own original colour and one
  // original 4-neighbour's.
  Image image(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      const bool on_line = y == static_cast<int>(20.0 + 0.2 * x);
      p[0] = p[1] = p[2] = on_line ? kDark : kLight;
      p[3] = 255;
    }
  const Image original = image;
  fxaa(image, 0, 0, kW, kH, nullptr);
  int changed = 0;
  for (int y = 1; y + 1 < kH; ++y)
    for (int x = 1; x + 1 < kW; ++x) {
      const int now = image.pixel(x, y)[0], was = original.pixel(x, y)[0];
      if (now == was) continue;
      ++changed;
      bool between = false;
      for (auto [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
        const int other = original.pixel(x + dx, y + dy)[0];
        between = between || (now >= std::min(was, other) && now <= std::max(was, other));
      }
      EXPECT_TRUE(between) << "at " << x << ", " << y;
    }
  EXPECT_GT(changed, 20);
}

}  // namespace
}  // namespace clothsim
