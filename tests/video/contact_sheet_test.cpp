#include "video/contact_sheet.h"

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
