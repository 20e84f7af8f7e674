#include "render/image_diff.h"

#include <gtest/gtest.h>

#include <cmath>

namespace clothsim {
namespace {

Image filled(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    }
  return image;
}

TEST(ImageDiff, IdenticalImagesDifferByNothing) {
  const Image a = filled(10, 10, 12, 34, 56);
  const DiffStats s = compare_images(a, a, 0);
  EXPECT_EQ(s.rms, 0.0);
  EXPECT_EQ(s.max, 0);
  EXPECT_EQ(s.over_fraction, 0.0);
  EXPECT_TRUE(within_tolerance(s, DiffTolerance{0, 0.0, 0.0}));
}

TEST(ImageDiff, RmsIsOverAllRgbChannelsOfAllPixels) {
  const Image a = filled(10, 10, 100, 100, 100);
  Image b = a;
  b.pixel(3, 7)[0] = 130;  // one channel of one pixel, 30 levels
  const DiffStats s = compare_images(a, b, 16);
  EXPECT_NEAR(s.rms, std::sqrt(30.0 * 30.0 / (3.0 * 100.0)), 1e-12);
  EXPECT_EQ(s.max, 30);
  EXPECT_DOUBLE_EQ(s.over_fraction, 0.01);
}

TEST(ImageDiff, APixelCountsAsDifferentOnlyPastTheThreshold) {
  const Image a = filled(4, 5, 50, 50, 50);
  Image b = a;
  b.pixel(0, 0)[1] = 66;  // 16: not past a threshold of 16
  b.pixel(1, 0)[2] = 67;  // 17: past it
  EXPECT_DOUBLE_EQ(compare_images(a, b, 16).over_fraction, 1.0 / 20.0);
  EXPECT_DOUBLE_EQ(compare_images(a, b, 15).over_fraction, 2.0 / 20.0);
  EXPECT_DOUBLE_EQ(compare_images(a, b, 17).over_fraction, 0.0);
}

TEST(ImageDiff, AlphaIsIgnored) {
  const Image a = filled(3, 3, 1, 2, 3);
  Image b = a;
  b.pixel(1, 1)[3] = 0;
  EXPECT_EQ(compare_images(a, b, 0).max, 0);
}

TEST(ImageDiff, ToleranceNeedsBothRmsAndShareWithinBounds) {
  const DiffTolerance tol{16, 2.0, 0.005};
  EXPECT_TRUE(within_tolerance(DiffStats{2.0, 200, 0.005}, tol));   // bounds are inclusive
  EXPECT_FALSE(within_tolerance(DiffStats{2.01, 20, 0.0}, tol));
  EXPECT_FALSE(within_tolerance(DiffStats{0.1, 20, 0.0051}, tol));
}

TEST(ImageDiff, DiffImageIsDimGreyWhereEqualAndHotWhereDifferent) {
  const Image a = filled(6, 4, 200, 200, 200);
  Image b = a;
  b.pixel(2, 1)[1] = 180;  // 20 levels
  const Image d = diff_image(a, b, 8);
  ASSERT_EQ(d.width, 6);
  ASSERT_EQ(d.height, 4);
  const std::uint8_t* same = d.pixel(0, 0);
  EXPECT_EQ(same[0], same[1]);
  EXPECT_EQ(same[1], same[2]);
  EXPECT_LT(same[0], 80);  // dimmed, so differences stand out
  const std::uint8_t* hot = d.pixel(2, 1);
  EXPECT_EQ(hot[0], 255);                // 20 x 8 x 3 = 480: red saturated, into yellow
  EXPECT_GT(hot[1], same[1] + 100);
  EXPECT_EQ(hot[3], 255);
}

TEST(ImageDiff, SizeMismatchGivesNoStatistics) {
  // The caller reports the mismatch itself (imgdiff names both files); nothing is read out of bounds.
  const DiffStats s = compare_images(filled(4, 4, 0, 0, 0), filled(5, 4, 255, 255, 255), 0);
  EXPECT_EQ(s.max, 0);
  EXPECT_EQ(s.rms, 0.0);
}

}  // namespace
}  // namespace clothsim
