#include "render/overlay_layout.h"

#include <gtest/gtest.h>

#include <string>

#include "render/synthetic_frames.h"
#include "render/text.h"

namespace clothsim::render {
namespace {

// A frame with everything drawn over it: overlay lines, a field with its bar, the inset.
RenderFrame busy_frame(int w, int h) {
  RenderFrame f;
  f.width = w;
  f.height = h;
  f.overlay_lines = {"drape  rk4  dt = 1e-4 s", "t = 1.500 s  force evals 60000"};
  f.cloth_positions.assign(3 * 4, 0.f);
  f.cloth_field = {1e-5f, 1e-4f, 1e-3f, 1e-2f};
  testing::set_error_scale(f);
  testing::show_energy_inset(f, 1.f, 0.f, 1.f);
  return f;
}

bool inside_image(const ImageBox& b, int w, int h) { return b.x >= 0 && b.y >= 0 && b.right() <= w && b.bottom() <= h; }

TEST(OverlayLayout, NothingCoversAnythingElseAtEveryTileSize) {
  for (const auto& [w, h] : {std::pair{320, 180}, std::pair{638, 358}, std::pair{640, 360}, std::pair{1280, 720},
                            std::pair{1920, 1080}, std::pair{360, 360}, std::pair{1080, 1080}}) {
    const OverlayLayout l = layout_overlay(busy_frame(w, h), w, h);
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    ASSERT_FALSE(l.text.empty());
    ASSERT_FALSE(l.color_bar.empty());
    ASSERT_FALSE(l.inset.empty());
    EXPECT_FALSE(l.text.overlaps(l.color_bar));
    EXPECT_FALSE(l.text.overlaps(l.inset));
    EXPECT_FALSE(l.color_bar.overlaps(l.inset));
    EXPECT_TRUE(inside_image(l.color_bar, w, h));  // (overlay lines are clipped by the caller's width)
    EXPECT_TRUE(inside_image(l.inset, w, h));
    // The colour bar at the right edge, the gradient inside its panel, at least a quarter as tall as the tile.
    EXPECT_EQ(l.color_bar.right(), w - l.margin);
    EXPECT_TRUE(l.color_bar.contains(l.bar.x, l.bar.y) && l.color_bar.contains(l.bar.right() - 1, l.bar.bottom() - 1));
    EXPECT_GE(l.bar.h, h / 4);
    // The inset bottom-right, above the band a tile label covers, about a quarter of the width.
    EXPECT_EQ(l.inset.right(), w - l.margin);
    EXPECT_LE(l.inset.bottom(), h - tile_label_band(l.scale));
    EXPECT_GE(l.inset.w, w / 4);
    EXPECT_LE(l.inset.w, w / 3);
    EXPECT_TRUE(l.inset.contains(l.plot.x, l.plot.y) && l.inset.contains(l.plot.right() - 1, l.plot.bottom() - 1));
    EXPECT_GE(l.ticks.size(), 3u) << "the decades 1e-6 .. 1e-1, thinned at most to every other";
  }
}

TEST(OverlayLayout, ABarSqueezedBetweenLongLinesAndTheInsetTakesTheHeightAndTheInsetMovesLeft) {
  // A compare tile of 398 x 223 with the CPU on its overlay: three lines of text reach across,
  // and between them and the inset the bar was a few pixels with its labels on each other.
  RenderFrame f = busy_frame(398, 223);
  f.overlay_lines = {"t = 1.200 s", "24530 force evals  582 ms cpu/sim s"};
  const OverlayLayout l = layout_overlay(f, 398, 223);
  ASSERT_FALSE(l.inset.empty());
  EXPECT_GE(l.bar.h, 3 * 10 * l.scale) << "room for three tick labels";
  EXPECT_GE(l.ticks.size(), 2u);
  EXPECT_FALSE(l.color_bar.overlaps(l.inset));
  EXPECT_FALSE(l.color_bar.overlaps(l.text));
  EXPECT_FALSE(l.inset.overlaps(l.text));
  EXPECT_LE(l.inset.right(), l.color_bar.x) << "left of the bar";
  EXPECT_LE(l.color_bar.bottom(), 223 - tile_label_band(l.scale));
  EXPECT_TRUE(l.inset.contains(l.plot.x, l.plot.y) && l.inset.contains(l.plot.right() - 1, l.plot.bottom() - 1));
}

TEST(OverlayLayout, TheTextScaleFollowsTheHeight) {
  EXPECT_EQ(layout_overlay(busy_frame(320, 180), 320, 180).scale, 1);
  EXPECT_EQ(layout_overlay(busy_frame(640, 360), 640, 360).scale, 2);
  EXPECT_EQ(layout_overlay(busy_frame(1280, 720), 1280, 720).scale, 4);
  EXPECT_EQ(layout_overlay(busy_frame(1920, 1080), 1920, 1080).scale, 6);
}

TEST(OverlayLayout, OverlayLinesAsWideAsTheImagePushTheColourBarBelowThem) {
  RenderFrame f = busy_frame(640, 360);
  f.overlay_lines = {std::string(50, 'x')};  // 50 glyphs at scale 2: most of 640 px
  const OverlayLayout l = layout_overlay(f, 640, 360);
  EXPECT_GT(l.color_bar.y, l.text.bottom() - 1);
  EXPECT_FALSE(l.color_bar.overlaps(l.inset));
}

TEST(OverlayLayout, ABarOnlyWithAFieldAndAnInsetOnlyWhenShown) {
  RenderFrame f = busy_frame(640, 360);
  f.cloth_field.clear();
  f.inset.show = false;
  OverlayLayout l = layout_overlay(f, 640, 360);
  EXPECT_TRUE(l.color_bar.empty());
  EXPECT_TRUE(l.inset.empty());
  f = busy_frame(640, 360);
  f.color_scale.show_bar = false;
  EXPECT_TRUE(layout_overlay(f, 640, 360).color_bar.empty());
}

TEST(OverlayLayout, TheInsetsTextIsTheOverlaysUnlessItsLabelWouldTakeAThirdOfTheWidth) {
  RenderFrame f = busy_frame(425, 358);  // a 3x2 tile of 1280x720
  EXPECT_EQ(layout_overlay(f, 425, 358).inset_scale, layout_overlay(f, 425, 358).scale);
  f.inset.label = "total energy of the cloth [J]";
  const OverlayLayout l = layout_overlay(f, 425, 358);
  EXPECT_LT(l.inset_scale, l.scale);
  EXPECT_LE(text_width(f.inset.label, l.inset_scale), l.inset.w);
}

}  // namespace
}  // namespace clothsim::render

namespace clothsim::render {

TEST(OverlayLayout, TheBannerFitsItsTileOnTwoLinesKeepingDivergedAndTheTime) {
  RenderFrame f;
  f.banner = {"DIVERGED", "at t = 0.0237 s", "(step 79)"};
  f.overlay_lines = {"t = 0.024 s", "79 force evals"};
  // Wide: one line, as it always was.
  const OverlayLayout wide = layout_overlay(f, 640, 360);
  EXPECT_EQ(wide.banner_lines, (std::vector<std::string>{"DIVERGED at t = 0.0237 s (step 79)"}));
  // A 2x2 tile of a 320x180 compare: the step on a line of its own.
  const OverlayLayout tile = layout_overlay(f, 158, 88);
  EXPECT_EQ(tile.banner_lines, (std::vector<std::string>{"DIVERGED at t = 0.0237 s", "(step 79)"}));
  // With the reason wrapped on three lines above it, two lines would cover the text: one, the
  // step left off, fits between the text and the label band.
  RenderFrame reason = f;
  reason.overlay_lines.push_back("diverged: kinetic energy 7.63e+08 J exceeds the bound 4.08e+08 J");
  const OverlayLayout under = layout_overlay(reason, 158, 88);
  EXPECT_EQ(under.banner_lines, (std::vector<std::string>{"DIVERGED at t = 0.0237 s"}));
  EXPECT_GE(under.banner.y, under.text.bottom());
  EXPECT_LE(under.banner.bottom(), 88 - tile_label_band(under.scale));
  // A 2x2 tile of a 200x120 compare: DIVERGED and the time; the step is left off.
  const OverlayLayout small = layout_overlay(f, 98, 58);
  EXPECT_EQ(small.banner_lines, (std::vector<std::string>{"DIVERGED", "at t = 0.0237 s"}));
  for (int w = 60; w <= 1280; w += 2) {
    const int h = w * 9 / 16;
    const OverlayLayout l = layout_overlay(f, w, h);
    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
    const int b = l.banner_scale;
    // The banner with its backdrop (2 scale around the glyphs) inside the tile, every line in its box.
    EXPECT_GE(l.banner.x - 2 * b, 0);
    EXPECT_LE(l.banner.right() + 2 * b, w);
    for (const std::string& line : l.banner_lines) EXPECT_LE(text_width(line, b), l.banner.w) << line;
    std::string all;
    for (const std::string& line : l.banner_lines) all += line + " ";
    EXPECT_EQ(all.rfind("DIVERGED ", 0), 0u) << all;
    EXPECT_NE(all.find("0.0237 s"), std::string::npos) << all;
    if (w >= 98) {  // (narrower, the time itself is wrapped: three lines, taller than a 33-row tile)
      EXPECT_LE(l.banner_lines.size(), 2u) << all;
      EXPECT_GE(l.banner.y - 2 * b, 0);
      EXPECT_LE(l.banner.bottom() + b, h);
    }
  }
}

TEST(OverlayLayout, AReasonTooLongForALineKeepsTheTextSize) {
  // A 2x2 tile of a 960x540 compare: WRONG's reason is one phrase wider than the tile. Broken at
  // spaces it stays at the overlay's scale, where packing whole phrases would shrink it to 1.
  RenderFrame f;
  f.banner = {"WRONG", "energy rose 1.8e+03 J with no work done on it"};
  const OverlayLayout l = layout_overlay(f, 413, 268);
  EXPECT_EQ(l.banner_scale, l.scale);
  ASSERT_EQ(l.banner_lines.size(), 3u);
  EXPECT_EQ(l.banner_lines[0], "WRONG");
  EXPECT_EQ(l.banner_lines[1] + " " + l.banner_lines[2], f.banner[1]);
  for (const std::string& line : l.banner_lines) EXPECT_LE(text_width(line, l.banner_scale), l.banner.w) << line;
}

TEST(OverlayLayout, ALineBreaksWhereItsPartsAreTwoSpacesApart) {
  // The cost line in that tile: passes and CPU on a line each, not "s" alone on the second.
  RenderFrame f;
  f.overlay_lines = {"22.1k passes/sim s  47 ms cpu/sim s"};
  const OverlayLayout l = layout_overlay(f, 413, 268);
  EXPECT_EQ(l.lines, (std::vector<std::string>{"22.1k passes/sim s", "  47 ms cpu/sim s"}));
  // A part too wide on its own is still broken at spaces, after the parts that fit.
  f.overlay_lines = {"t = 1 s  diverged: kinetic energy 7.63e+08 J exceeds the bound 4.08e+08 J"};
  const OverlayLayout narrow = layout_overlay(f, 320, 180);
  ASSERT_GE(narrow.lines.size(), 3u);
  EXPECT_EQ(narrow.lines[0], "t = 1 s");
  for (std::size_t i = 1; i < narrow.lines.size(); ++i) EXPECT_EQ(narrow.lines[i].rfind("  ", 0), 0u) << narrow.lines[i];
}

TEST(OverlayLayout, LongLinesWrapAtSpacesToTheImagesWidth) {
  RenderFrame f;
  f.overlay_lines = {"t = 0.024 s", "diverged: kinetic energy 7.63e+08 J exceeds the bound 4.08e+08 J"};
  const OverlayLayout wide = layout_overlay(f, 1280, 360);
  EXPECT_EQ(wide.lines, f.overlay_lines) << "room enough: as given";
  const OverlayLayout narrow = layout_overlay(f, 320, 360);
  ASSERT_GT(narrow.lines.size(), 2u);
  EXPECT_EQ(narrow.lines[0], "t = 0.024 s");
  EXPECT_EQ(narrow.lines[1].rfind("diverged: ", 0), 0u);
  std::string rejoined;
  for (std::size_t i = 1; i < narrow.lines.size(); ++i) {
    EXPECT_LE(text_width(narrow.lines[i], narrow.scale), 320 - 2 * narrow.margin) << narrow.lines[i];
    if (i > 1) {
      EXPECT_EQ(narrow.lines[i].rfind("  ", 0), 0u) << "continuations are indented";
    }
    rejoined += (i > 1 ? " " : "") + narrow.lines[i].substr(i > 1 ? 2 : 0);
  }
  EXPECT_EQ(rejoined, f.overlay_lines[1]) << "no word lost";
  EXPECT_GE(narrow.text.h, static_cast<int>(narrow.lines.size()) * text_glyph_height() * narrow.scale);
}

}  // namespace clothsim::render
