#include "render/video/contact_sheet.h"

#include <gtest/gtest.h>

using namespace clothsim;

namespace {

Image solid(int w, int h, std::uint8_t v) {
  Image image(w, h);
  fill_rect(image, 0, 0, w, h, Rgba8{v, v, v, 255});
  return image;
}

int text_pixels(const Image& image, int x, int y, int w, int h, Rgba8 background) {
  int n = 0;
  for (int yy = y; yy < y + h; ++yy)
    for (int xx = x; xx < x + w; ++xx) {
      const auto* p = image.pixel(xx, yy);
      n += p[0] != background[0] || p[1] != background[1] || p[2] != background[2];
    }
  return n;
}

}  // namespace

TEST(ContactSheet, PutsRowsAndColumnsInOrderWithLabelsAlongTheEdges) {
  // Cell (r, c) has grey level 40 + 50 r + 10 c, so every cell is identifiable.
  std::vector<std::vector<Image>> cells(3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 2; ++c) cells[r].push_back(solid(80, 45, 40 + 50 * r + 10 * c));
  const TilingStyle style;
  const Image sheet = compose_contact_sheet(cells, {"explicit_euler", "midpoint", "rk4"},
                                            {"t = 0.5 s", "t = 1 s"}, style);
  ASSERT_GT(sheet.width, 2 * 80);
  ASSERT_GT(sheet.height, 3 * 45);

  // Find the grid: the first cell's colour, scanning the middle of the first row.
  int left = -1, top = -1;
  for (int x = 0; x < sheet.width && left < 0; ++x)
    for (int y = 0; y < sheet.height && left < 0; ++y)
      if (sheet.pixel(x, y)[0] == 40) left = x, top = y;
  ASSERT_GE(left, 0);
  EXPECT_GT(left, 0) << "room on the left for row labels";
  EXPECT_GT(top, 0) << "room on top for column labels";
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 2; ++c) {
      const int x = left + c * (80 + style.gutter) + 40, y = top + r * (45 + style.gutter) + 22;
      EXPECT_EQ(sheet.pixel(x, y)[0], 40 + 50 * r + 10 * c) << "cell " << r << "," << c;
    }
  for (int r = 0; r < 3; ++r)
    EXPECT_GT(text_pixels(sheet, 0, top + r * (45 + style.gutter), left, 45, style.background), 10)
        << "row label " << r;
  for (int c = 0; c < 2; ++c)
    EXPECT_GT(text_pixels(sheet, left + c * (80 + style.gutter), 0, 80, top, style.background), 10)
        << "column label " << c;
}

TEST(ContactSheet, RefusesCellsThatDoNotMatchTheLabels) {
  std::vector<std::vector<Image>> cells(2, std::vector<Image>(2, solid(8, 8, 100)));
  EXPECT_THROW(compose_contact_sheet(cells, {"a"}, {"1", "2"}), std::invalid_argument);
  EXPECT_THROW(compose_contact_sheet(cells, {"a", "b"}, {"1", "2", "3"}), std::invalid_argument);
}

TEST(ContactSheet, RowAndColumnLabelsScaleWithTheCellsAsTileLabelsDo) {
  // One 640x360 cell under the column label "H": the rows of white ink above the cell are
  // its cap height, 14 px at scale 2 (the row label sits beside the cell, lower down).
  std::vector<std::vector<Image>> cells{{solid(640, 360, 90)}};
  const Image sheet = compose_contact_sheet(cells, {"rk4"}, {"H"});
  int cell_top = 0;
  while (cell_top < sheet.height && sheet.pixel(sheet.width / 2, cell_top)[0] != 90) ++cell_top;
  int rows = 0;
  for (int y = 0; y < cell_top; ++y) {
    bool ink = false;
    for (int x = 0; x < sheet.width && !ink; ++x) ink = sheet.pixel(x, y)[0] == 255 && sheet.pixel(x, y)[2] == 255;
    rows += ink;
  }
  EXPECT_EQ(rows, 14);
}

TEST(ContactSheet, IsExactlyTheAskedSizeWithCellsShrunkToFit) {
  // Four 640x360 cells in a row would make a sheet over 2560 px wide; asked for 960x540 it
  // is 960x540, its cells shrunk alike (aspect kept) and still in order.
  std::vector<std::vector<Image>> cells(2);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 4; ++c) cells[r].push_back(solid(640, 360, 40 + 50 * r + 10 * c));
  const TilingStyle style;
  const Image sheet = compose_contact_sheet(cells, {"explicit_euler", "rk4"}, {"0.1", "0.5", "2", "4"}, style, 960, 540);
  EXPECT_EQ(sheet.width, 960);
  EXPECT_EQ(sheet.height, 540);
  int left = -1, top = -1;
  for (int y = 0; y < sheet.height && left < 0; ++y)
    for (int x = 0; x < sheet.width && left < 0; ++x)
      if (sheet.pixel(x, y)[0] == 40) left = x, top = y;
  ASSERT_GE(left, 0);
  int cell_w = 0;
  while (sheet.pixel(left + cell_w, top)[0] == 40) ++cell_w;
  EXPECT_LT(cell_w, 240) << "four cells and the row labels in 960 px";
  EXPECT_GT(cell_w, 150);
  EXPECT_EQ(sheet.pixel(left + 3 * (cell_w + style.gutter) + cell_w / 2, top + 5)[0], 70) << "the fourth column";
  EXPECT_GT(text_pixels(sheet, 0, top, left, cell_w / 2, style.background), 10) << "the row label stays";
}

TEST(ContactSheet, SmallCellsAreCentredNotEnlarged) {
  std::vector<std::vector<Image>> cells{{solid(80, 45, 90)}};
  const Image sheet = compose_contact_sheet(cells, {"rk4"}, {"1"}, TilingStyle{}, 400, 300);
  EXPECT_EQ(sheet.width, 400);
  EXPECT_EQ(sheet.height, 300);
  int n = 0;
  for (int y = 0; y < sheet.height; ++y)
    for (int x = 0; x < sheet.width; ++x) n += sheet.pixel(x, y)[0] == 90;
  EXPECT_EQ(n, 80 * 45);
}

TEST(Downscale, AveragesThePixelsEachOutputPixelCovers) {
  Image src(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const auto v = static_cast<std::uint8_t>(x < 2 ? 100 : 200);
      std::uint8_t* p = src.pixel(x, y);
      p[0] = p[1] = p[2] = v;
      p[3] = 255;
    }
  const Image out = downscale(src, 2, 1);
  EXPECT_EQ(out.pixel(0, 0)[0], 100);
  EXPECT_EQ(out.pixel(1, 0)[0], 200);
  EXPECT_EQ(out.pixel(1, 0)[3], 255);
}

TEST(ContactSheet, ASpanDrawsTheRestOfItsRowAsOneCellOfTextInPlaceOfItsCells) {
  // Row 1 diverged after its first cell: cells 1..3 become one panel with two lines of text.
  std::vector<std::vector<Image>> cells(2);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 4; ++c) cells[r].push_back(solid(120, 60, 40 + 50 * r + 10 * c));
  const TilingStyle style;
  const std::vector<std::string> rows{"rk2", "rk4"}, columns{"a", "b", "c", "d"};
  const Image plain = compose_contact_sheet(cells, rows, columns, style);
  const Image spanned = compose_contact_sheet(cells, rows, columns, style, 0, 0,
                                              {SheetSpan{1, 1, {"DIVERGED at t = 0.02 s", "stable below ~1e-4 s"}}});
  ASSERT_EQ(spanned.width, plain.width);
  ASSERT_EQ(spanned.height, plain.height);
  int left = -1, top = -1;  // the first cell, as above
  for (int x = 0; x < plain.width && left < 0; ++x)
    for (int y = 0; y < plain.height && left < 0; ++y)
      if (plain.pixel(x, y)[0] == 40) left = x, top = y;
  ASSERT_GE(left, 0);
  const int step_x = 120 + style.gutter, row1 = top + 60 + style.gutter;
  for (int c = 0; c < 4; ++c)  // row 0 and row 1's first cell untouched
    EXPECT_EQ(spanned.pixel(left + c * step_x + 5, top + 5)[0], 40 + 10 * c) << c;
  EXPECT_EQ(spanned.pixel(left + 5, row1 + 5)[0], 90);
  // The span covers cells 1..3 and the gutters between them: one panel colour at its corners.
  const int x0 = left + step_x, x1 = left + 4 * step_x - style.gutter - 1;
  const std::uint8_t* panel = spanned.pixel(x0, row1);
  EXPECT_NE(panel[0], 100) << "cell 1's own colour is gone";
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{x1, row1}, {x0, row1 + 59}, {x1, row1 + 59},
                                                             {left + 2 * step_x - 2, row1 + 2}})
    EXPECT_TRUE(std::equal(panel, panel + 3, spanned.pixel(x, y))) << x << "," << y;
  Rgba8 background{panel[0], panel[1], panel[2], 255};
  EXPECT_GT(text_pixels(spanned, x0, row1, x1 - x0, 60, background), 50) << "its lines are drawn";
  // The red of the first line (DIVERGED) is in the span.
  bool red = false;
  for (int y = row1; y < row1 + 60 && !red; ++y)
    for (int x = x0; x < x1 && !red; ++x) red = spanned.pixel(x, y)[0] == 255 && spanned.pixel(x, y)[1] == 72;
  EXPECT_TRUE(red);
  EXPECT_THROW(compose_contact_sheet(cells, rows, columns, style, 0, 0, {SheetSpan{2, 0, {"x"}}}), std::invalid_argument);
}
