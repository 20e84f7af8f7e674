#include "render/text.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "render/synthetic_frames.h"

namespace clothsim {
namespace {

using testing::grey_image;

constexpr Rgba8 kWhite{255, 255, 255, 255};
constexpr Rgba8 kRed{250, 10, 20, 255};

bool is(const std::uint8_t* p, Rgba8 c) { return p[0] == c[0] && p[1] == c[1] && p[2] == c[2]; }

int count_colour(const Image& image, Rgba8 c) {
  int n = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) n += is(image.pixel(x, y), c);
  return n;
}

// The glyph of `c` at scale 1 as a string of '#' and '.', for comparing glyphs.
std::string glyph_pattern(char c) {
  Image image = grey_image(text_glyph_width(), text_glyph_height());
  draw_text(image, 0, 0, std::string(1, c), kWhite, 1, false);
  std::string pattern;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) pattern += is(image.pixel(x, y), kWhite) ? '#' : '.';
  return pattern;
}

TEST(Text, TheScaleForAHeightGivesACapHeightOfAThirtiethOfItAndNoMore) {
  EXPECT_EQ(text_scale_for_height(180), 1);   // cap 7 px
  EXPECT_EQ(text_scale_for_height(360), 2);   // 14 px
  EXPECT_EQ(text_scale_for_height(720), 4);   // 28 px
  EXPECT_EQ(text_scale_for_height(1080), 6);  // 42 px
  for (int h = 1; h <= 2160; ++h) {
    const int s = text_scale_for_height(h);
    ASSERT_GE(30 * kTextCapHeight * s, h) << h;
    if (s > 1) {
      ASSERT_LT(30 * kTextCapHeight * (s - 1), h) << h << ": one step smaller would do";
    }
  }
}

TEST(Text, TheCapHeightIsThatOfTheFontsH) {
  Image image = grey_image(text_glyph_width(), text_glyph_height());
  draw_text(image, 0, 0, "H", kWhite, 1, false);
  int rows = 0;
  for (int y = 0; y < image.height; ++y) {
    bool ink = false;
    for (int x = 0; x < image.width; ++x) ink = ink || is(image.pixel(x, y), kWhite);
    rows += ink;
  }
  EXPECT_EQ(rows, kTextCapHeight);
}

TEST(Text, WidthIsOneCellPerCharacterLessTheLastGap) {
  EXPECT_EQ(text_width("", 3), 0);
  EXPECT_EQ(text_width("a", 1), text_glyph_width() - 1);
  EXPECT_EQ(text_width("abcd", 2), (4 * text_glyph_width() - 1) * 2);
}

TEST(Text, EveryPrintableCharacterButSpaceHasInkAndAGlyphOfItsOwn) {
  std::set<std::string> seen;
  EXPECT_EQ(glyph_pattern(' ').find('#'), std::string::npos);
  for (char c = 33; c < 127; ++c) {
    const std::string pattern = glyph_pattern(c);
    EXPECT_NE(pattern.find('#'), std::string::npos) << "'" << c << "' has no ink";
    EXPECT_TRUE(seen.insert(pattern).second) << "'" << c << "' looks like another character";
  }
}

TEST(Text, UnknownCharactersDrawAsAQuestionMark) {
  EXPECT_EQ(glyph_pattern('\x01'), glyph_pattern('?'));
  EXPECT_EQ(glyph_pattern('\xe9'), glyph_pattern('?'));
}

TEST(Text, InkStaysInsideTheTextBoxAndScalesByWholePixels) {
  const std::string s = "t = 1.25 s";
  for (int scale : {1, 2, 3}) {
    Image image = grey_image(200, 60);
    draw_text(image, 10, 20, s, kRed, scale, false);
    const int w = text_width(s, scale), h = text_glyph_height() * scale;
    int inside = 0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        if (is(image.pixel(x, y), kRed)) {
          EXPECT_TRUE(x >= 10 && x < 10 + w && y >= 20 && y < 20 + h) << x << "," << y;
          ++inside;
        }
    Image one = grey_image(200, 60);
    draw_text(one, 10, 20, s, kRed, 1, false);
    EXPECT_EQ(inside, count_colour(one, kRed) * scale * scale) << "scale " << scale;
  }
}

TEST(Text, BackdropDarkensAroundTheTextOnly) {
  Image image = grey_image(120, 40, 200);
  draw_text(image, 20, 10, "DIVERGED", kRed, 1, true);
  EXPECT_LT(image.pixel(19, 12)[0], 100);  // just left of the first glyph: darkened
  EXPECT_EQ(image.pixel(5, 5)[0], 200);    // far away: untouched
  EXPECT_EQ(image.pixel(118, 38)[0], 200);
}

TEST(Text, ABlockSharesOneBackdropWithoutDarkerBands) {
  Image image = grey_image(160, 80, 200);
  draw_text_block(image, 8, 8, {"scene: drape", "t = 0.500 s"}, kWhite, 1);
  // Between the two lines, the backdrop was applied once: same darkness as above the first line.
  const int between = 8 + text_glyph_height() - 1;
  EXPECT_EQ(image.pixel(7, between)[0], image.pixel(7, 7)[0]);
}

TEST(Text, IsClippedAtTheImageEdges) {
  Image image = grey_image(30, 12);
  draw_text(image, -7, -4, "clipped text", kWhite, 2, true);
  draw_text(image, 25, 8, "edge", kWhite, 3, true);
  EXPECT_GT(count_colour(image, kWhite), 0);
  EXPECT_EQ(image.rgba.size(), 30u * 12u * 4u);
}

}  // namespace
}  // namespace clothsim
