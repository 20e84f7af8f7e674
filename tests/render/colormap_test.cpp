#include "render/colormap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace clothsim::render {
namespace {

// CIE 1976 L* of a display sRGB colour (IEC 61966-2-1 transfer, D65 luminance weights).
double lightness(const Rgb& c) {
  const auto linear = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
  const double y = 0.2126 * linear(c[0]) + 0.7152 * linear(c[1]) + 0.0722 * linear(c[2]);
  return y > 216.0 / 24389.0 ? 116.0 * std::cbrt(y) - 16.0 : y * 24389.0 / 27.0;
}

TEST(Colormap, LightnessRisesMonotonicallyFromDarkToLight) {
  double previous = -1.0;
  for (int i = 0; i <= 1024; ++i) {
    const double l = lightness(colormap(static_cast<float>(i) / 1024.f));
    EXPECT_GT(l, previous) << "at " << i << "/1024";
    previous = l;
  }
  EXPECT_LT(lightness(colormap(0.f)), 20.0);  // viridis: L* about 16 ...
  EXPECT_GT(lightness(colormap(1.f)), 90.0);  // ... to about 92
}

TEST(Colormap, EndsAreViridisDarkPurpleAndYellowAndOutsideIsClamped) {
  const Rgb lo = colormap(0.f), hi = colormap(1.f);
  EXPECT_FLOAT_EQ(lo[0], 0.267004f);
  EXPECT_FLOAT_EQ(lo[1], 0.004874f);
  EXPECT_FLOAT_EQ(lo[2], 0.329415f);
  EXPECT_FLOAT_EQ(hi[0], 0.993248f);
  EXPECT_FLOAT_EQ(hi[1], 0.906157f);
  EXPECT_FLOAT_EQ(hi[2], 0.143936f);
  EXPECT_EQ(colormap(-3.f), lo);
  EXPECT_EQ(colormap(7.f), hi);
  EXPECT_EQ(colormap(std::numeric_limits<float>::quiet_NaN()), lo);
  EXPECT_EQ(colormap_rgb8(0.f), (std::array<std::uint8_t, 3>{68, 1, 84}));
  EXPECT_EQ(colormap_rgb8(1.f), (std::array<std::uint8_t, 3>{253, 231, 37}));
  // Blue-teal in the middle (matplotlib's viridis(0.5) = (0.128, 0.567, 0.551)).
  const Rgb mid = colormap(0.5f);
  EXPECT_NEAR(mid[0], 0.127568f, 1e-6f);
  EXPECT_NEAR(mid[1], 0.566949f, 1e-6f);
}

TEST(ScalePosition, ALogScaleSpacesDecadesEvenlyAndSendsWhatHasNoLogToTheLowEnd) {
  ColorScale s;
  s.lo = 1e-6f;
  s.hi = 1e-1f;
  EXPECT_NEAR(scale_position(s, 1e-6f), 0.f, 1e-5f);
  EXPECT_NEAR(scale_position(s, 1e-4f), 0.4f, 1e-5f);
  EXPECT_NEAR(scale_position(s, 1e-1f), 1.f, 1e-5f);
  EXPECT_EQ(scale_position(s, 10.f), 1.f);
  EXPECT_EQ(scale_position(s, 1e-9f), 0.f);
  EXPECT_EQ(scale_position(s, 0.f), 0.f);
  EXPECT_EQ(scale_position(s, -1.f), 0.f);
  EXPECT_EQ(scale_position(s, std::numeric_limits<float>::quiet_NaN()), 0.f);
  EXPECT_EQ(scale_position(s, std::numeric_limits<float>::infinity()), 0.f);
}

TEST(ScalePosition, ALinearScaleIsLinearAndClamped) {
  ColorScale s;
  s.log = false;
  s.lo = -1.f;
  s.hi = 3.f;
  EXPECT_FLOAT_EQ(scale_position(s, -1.f), 0.f);
  EXPECT_FLOAT_EQ(scale_position(s, 0.f), 0.25f);
  EXPECT_FLOAT_EQ(scale_position(s, 3.f), 1.f);
  EXPECT_FLOAT_EQ(scale_position(s, 9.f), 1.f);
  EXPECT_FLOAT_EQ(scale_position(s, -9.f), 0.f);
}

std::vector<std::string> texts(const std::vector<ScaleTick>& ticks) {
  std::vector<std::string> out;
  for (const ScaleTick& t : ticks) out.push_back(t.text);
  return out;
}

TEST(ScaleTicks, ALogScaleIsLabelledAtItsDecades) {
  ColorScale s;
  s.lo = 1e-6f;
  s.hi = 1e-1f;
  const auto ticks = scale_ticks(s, 10);
  EXPECT_EQ(texts(ticks), (std::vector<std::string>{"1e-6", "1e-5", "1e-4", "1e-3", "1e-2", "1e-1"}));
  EXPECT_NEAR(ticks[2].position, 0.4f, 1e-5f);
  s.lo = 0.01f;
  s.hi = 10.f;
  EXPECT_EQ(texts(scale_ticks(s, 10)), (std::vector<std::string>{"0.01", "0.1", "1", "10"}));
}

TEST(ScaleTicks, TooManyDecadesForTheBarAreThinnedToRoundExponents) {
  ColorScale s;
  s.lo = 1e-12f;
  s.hi = 1.f;
  EXPECT_EQ(texts(scale_ticks(s, 5)), (std::vector<std::string>{"1e-12", "1e-9", "1e-6", "1e-3", "1e0"}));
  // Counted from the top decade, so the bar's upper end is labelled: 1e-5 .. 1e-1 in three.
  s.lo = 1e-5f;
  s.hi = 1e-1f;
  EXPECT_EQ(texts(scale_ticks(s, 3)), (std::vector<std::string>{"1e-5", "1e-3", "1e-1"}));
}

TEST(ScaleTicks, LessThanTwoDecadesAreLabelledAtTheEnds) {
  ColorScale s;
  s.lo = 2e-3f;
  s.hi = 3e-2f;
  const auto ticks = scale_ticks(s, 6);
  EXPECT_EQ(texts(ticks), (std::vector<std::string>{"0.002", "0.03"}));
  EXPECT_FLOAT_EQ(ticks[0].position, 0.f);
  EXPECT_FLOAT_EQ(ticks[1].position, 1.f);
}

TEST(ScaleTicks, ALinearScaleIsLabelledAtRoundValues) {
  ColorScale s;
  s.log = false;
  s.lo = 0.f;
  s.hi = 1.f;
  EXPECT_EQ(texts(scale_ticks(s, 6)), (std::vector<std::string>{"0", "0.2", "0.4", "0.6", "0.8", "1"}));
  s.hi = 0.37f;
  EXPECT_EQ(texts(scale_ticks(s, 5)), (std::vector<std::string>{"0", "0.1", "0.2", "0.3"}));
}

TEST(ShortNumber, KeepsThreeDigitsAndACompactExponent) {
  EXPECT_EQ(short_number(0.0), "0");
  EXPECT_EQ(short_number(1.5e-5), "1.5e-5");
  EXPECT_EQ(short_number(2500.0), "2.5e3");
  EXPECT_EQ(short_number(123.456), "123");
  EXPECT_EQ(short_number(-0.25), "-0.25");
}

}  // namespace
}  // namespace clothsim::render
