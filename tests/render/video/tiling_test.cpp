#include "render/video/tiling.h"

#include <gtest/gtest.h>

#include <string>

using namespace clothsim;

namespace {

Image solid(int w, int h, Rgba8 c) {
  Image image(w, h);
  fill_rect(image, 0, 0, w, h, c);
  return image;
}

bool same_rgb(const std::uint8_t* p, Rgba8 c) { return p[0] == c[0] && p[1] == c[1] && p[2] == c[2]; }

int pixels_not(const Image& image, int x, int y, int w, int h, Rgba8 c) {
  int n = 0;
  for (int yy = y; yy < y + h; ++yy)
    for (int xx = x; xx < x + w; ++xx) n += !same_rgb(image.pixel(xx, yy), c);
  return n;
}

std::string layout_error(const std::string& text, int tiles) {
  try {
    parse_layout(text, tiles);
  } catch (const LayoutError& e) {
    return e.what();
  }
  return "";
}

const Rgba8 kRed{220, 30, 30, 255}, kGreen{30, 200, 40, 255}, kBlue{40, 50, 230, 255},
    kYellow{240, 230, 40, 255};

}  // namespace

TEST(ParseLayout, ReadsColumnsByRows) {
  const GridLayout square = parse_layout("2x2", 4);
  EXPECT_EQ(square.columns, 2);
  EXPECT_EQ(square.rows, 2);
  const GridLayout row = parse_layout("4x1", 4);
  EXPECT_EQ(row.columns, 4);
  EXPECT_EQ(row.rows, 1);
  const GridLayout three_by_two = parse_layout("3x2", 5);
  EXPECT_EQ(three_by_two.columns, 3);
  EXPECT_EQ(three_by_two.rows, 2);
}

TEST(ParseLayout, ExpandsNToTheNumberOfTiles) {
  const GridLayout row = parse_layout("Nx1", 3);
  EXPECT_EQ(row.columns, 3);
  EXPECT_EQ(row.rows, 1);
  const GridLayout column = parse_layout("1xN", 3);
  EXPECT_EQ(column.columns, 1);
  EXPECT_EQ(column.rows, 3);
}

TEST(ParseLayout, AutoPicksTheSquarestGridThatHoldsTheTiles) {
  EXPECT_EQ(parse_layout("auto", 1).cells(), 1);
  EXPECT_EQ(parse_layout("auto", 2).columns, 2);
  EXPECT_EQ(parse_layout("auto", 2).rows, 1);
  EXPECT_EQ(parse_layout("auto", 3).columns, 2);
  EXPECT_EQ(parse_layout("auto", 3).rows, 2);
  EXPECT_EQ(parse_layout("auto", 4).columns, 2);
  EXPECT_EQ(parse_layout("auto", 5).columns, 3);
  EXPECT_EQ(parse_layout("auto", 5).rows, 2);
}

TEST(ParseLayout, AllowsSpareCellsAtTheEndOfTheLastRow) {
  EXPECT_EQ(parse_layout("2x2", 3).cells(), 4);
}

TEST(ParseLayout, RejectsUnknownLayoutsNamingThemAndTheForms) {
  for (const char* bad : {"", "grid", "2by2", "x2", "2x", "0x4", "2x0", "-1x4"}) {
    const std::string message = layout_error(bad, 4);
    EXPECT_NE(message.find("unknown layout '" + std::string(bad) + "'"), std::string::npos)
        << bad << " -> " << message;
    EXPECT_NE(message.find("2x2"), std::string::npos) << message;
  }
}

TEST(ParseLayout, RejectsGridsTooSmallOrWithAnEmptyRowOrColumn) {
  EXPECT_NE(layout_error("2x2", 5).find("4 cells for 5 tiles"), std::string::npos);
  EXPECT_NE(layout_error("3x3", 4).find("empty"), std::string::npos);
  EXPECT_NE(layout_error("5x1", 4).find("empty"), std::string::npos);
  EXPECT_NE(layout_error("NxN", 4).find("empty"), std::string::npos);
}

TEST(TileGrid, PlacesTilesRowByRowWithGuttersBetween) {
  TilingStyle style;
  style.gutter = 4;
  const TileGrid grid(GridLayout{2, 2}, 20, 10, style);
  EXPECT_EQ(grid.width(), 44);
  EXPECT_EQ(grid.height(), 24);
  const Image a = solid(20, 10, kRed), b = solid(20, 10, kGreen), c = solid(20, 10, kBlue),
              d = solid(20, 10, kYellow);
  Image out;
  grid.compose({&a, &b, &c, &d}, {}, out);
  EXPECT_TRUE(same_rgb(out.pixel(10, 5), kRed));      // top-left
  EXPECT_TRUE(same_rgb(out.pixel(34, 5), kGreen));    // top-right
  EXPECT_TRUE(same_rgb(out.pixel(10, 19), kBlue));    // bottom-left
  EXPECT_TRUE(same_rgb(out.pixel(34, 19), kYellow));  // bottom-right
  EXPECT_EQ(pixels_not(out, 20, 0, 4, 24, style.background), 0) << "vertical gutter";
  EXPECT_EQ(pixels_not(out, 0, 10, 44, 4, style.background), 0) << "horizontal gutter";
}

TEST(TileGrid, LeavesSpareCellsAsBackground) {
  const TileGrid grid(GridLayout{2, 2}, 8, 8);
  const Image a = solid(8, 8, kRed);
  Image out;
  grid.compose({&a, &a, &a}, {}, out);
  EXPECT_EQ(pixels_not(out, grid.cell_x(3), grid.cell_y(3), 8, 8, TilingStyle{}.background), 0);
}

TEST(TileGrid, DrawsEachLabelInsideItsTileAndOnlyThere) {
  const TileGrid grid(GridLayout{2, 1}, 120, 60);
  const Image a = solid(120, 60, kBlue), b = solid(120, 60, kBlue);
  Image out;
  grid.compose({&a, &b}, {"rk4", ""}, out);
  EXPECT_GT(pixels_not(out, grid.cell_x(0), grid.cell_y(0), 120, 60, kBlue), 20)
      << "the labelled tile has text pixels";
  EXPECT_EQ(pixels_not(out, grid.cell_x(1), grid.cell_y(1), 120, 60, kBlue), 0)
      << "an empty label draws nothing";
  // Bottom-left: the top half of the labelled tile is untouched.
  EXPECT_EQ(pixels_not(out, grid.cell_x(0), grid.cell_y(0), 120, 30, kBlue), 0);
}

TEST(TileGrid, ShrinksALongLabelToItsTileRatherThanSpillingIntoTheNext) {
  TilingStyle style;
  style.label_scale = 3;  // "abcdefgh" is 144 px wide at scale 3, 48 at scale 1
  const TileGrid grid(GridLayout{2, 1}, 60, 40, style);
  const Image a = solid(60, 40, kBlue), b = solid(60, 40, kBlue);
  Image out;
  grid.compose({&a, &b}, {"abcdefgh", ""}, out);
  EXPECT_GT(pixels_not(out, grid.cell_x(0), 0, 60, 40, kBlue), 20);
  EXPECT_EQ(pixels_not(out, 60, 0, 4, 40, style.background), 0) << "gutter untouched";
  EXPECT_EQ(pixels_not(out, grid.cell_x(1), 0, 60, 40, kBlue), 0) << "next tile untouched";
}

TEST(FitLabel, ShortensWithAnEllipsisKeepingTheFirstWordWhole) {
  // 158 px (a 2x2 tile of a 320x180 compare) holds 25 glyphs at scale 1 with the margins.
  EXPECT_EQ(fit_label("midpoint  dt = 0.0001 s", 158, 1), "midpoint  dt = 0.0001 s") << "fits: as given";
  EXPECT_EQ(fit_label("implicit_euler (fixed point)  dt = 0.0001 s", 158, 1), "implicit_euler (fixed...");
  EXPECT_EQ(fit_label("implicit_euler (fixed point)  dt = 0.0001 s", 110, 1), "implicit_euler...")
      << "the name whole rather than a piece of what follows it";
  EXPECT_EQ(fit_label("implicit_euler", 70, 1), "implici...") << "a tile narrower than the name";
  EXPECT_EQ(fit_label("implicit_euler", 20, 1), "") << "not even the ellipsis fits: no label";
}

TEST(FitLabel, KeepsALanesStepWholeAndShortensItsName) {
  // A lane as --integrators spells it has no space: cut at its end, two lanes of one integrator
  // read "symplectic_e..." alike. The step stays and the name gives way.
  EXPECT_EQ(fit_label("symplectic_euler@1e-4", 98, 1), "symplec...@1e-4");  // 98 px: 15 glyphs
  EXPECT_EQ(fit_label("symplectic_euler@2e-4", 98, 1), "symplec...@2e-4");
  EXPECT_EQ(fit_label("implicit_euler_fixed_point@0.0001", 158, 1), "implicit_euler...@0.0001")
      << "no '_' left dangling before the ellipsis";
  EXPECT_EQ(fit_label("implicit_euler_fixed_point@0.0001", 110, 1), "implici...@0.0001");
  EXPECT_EQ(fit_label("midpoint@0.0001", 98, 1), "midpoint@0.0001") << "fits: as given";
  EXPECT_EQ(fit_label("implicit_euler@0.0001", 70, 1), "implici...")
      << "no room for a letter of the name beside the step: the name's start rather than the step alone";
  for (int width : {70, 98, 110, 158})
    for (int scale : {1, 2}) {
      const std::string fitted = fit_label("implicit_euler_fixed_point@1/60", width, scale);
      if (!fitted.empty()) {
        EXPECT_TRUE(label_fits(fitted, width, scale)) << fitted << " in " << width << " px";
      }
    }
}

TEST(FitLabels, LabelsThatWouldShortenAlikeAreCutInTheMiddleToStayApart) {
  // Two names with one start at one step: "impli...@0.0001" twice in a 98 px tile.
  const std::vector<std::string> given{"implicit_euler@0.0001", "implicit_euler_fixed_point@0.0001",
                                       "midpoint@0.0001", "rk4@0.0001"};
  EXPECT_EQ(fit_label(given[0], 98, 1), fit_label(given[1], 98, 1));
  const std::vector<std::string> shown = fit_labels(given, 98, 1);
  EXPECT_EQ(shown, (std::vector<std::string>{"imp...er@0.0001", "imp...nt@0.0001", "midpoint@0.0001", "rk4@0.0001"}));
  // A step apart: distinct as fit_label shortens them, left as they are.
  EXPECT_EQ(fit_labels({"symplectic_euler@1e-4", "symplectic_euler@2e-4"}, 98, 1),
            (std::vector<std::string>{"symplec...@1e-4", "symplec...@2e-4"}));
  // Narrower than a name and a step: the names' ends tell them apart.
  const std::vector<std::string> narrow = fit_labels(given, 64, 1);  // 9 glyphs
  EXPECT_NE(narrow[0], narrow[1]) << narrow[0];
  // At every width where they are shortened: distinct, and each fits.
  for (int width = 50; width <= 220; width += 4) {
    const std::vector<std::string> fitted = fit_labels(given, width, 1);
    for (std::size_t i = 0; i < fitted.size(); ++i) {
      if (!fitted[i].empty()) {
        EXPECT_TRUE(label_fits(fitted[i], width, 1)) << fitted[i] << " in " << width << " px";
      }
      for (std::size_t j = i + 1; j < fitted.size() && width >= 64; ++j)
        EXPECT_NE(fitted[i], fitted[j]) << "in " << width << " px";
    }
  }
}

// The columns [first, last] of `tile` (x, w) where `out` differs from `fill` in the bottom
// rows `band`: where a label, its backdrop included, was drawn. {-1, -1} for nothing.
std::pair<int, int> drawn_columns(const Image& out, int x, int w, int h, int band, Rgba8 fill) {
  int first = -1, last = -1;
  for (int xx = x; xx < x + w; ++xx)
    for (int y = h - band; y < h; ++y)
      if (!same_rgb(out.pixel(xx, y), fill)) {
        if (first < 0) first = xx;
        last = xx;
      }
  return {first, last};
}

TEST(TileGrid, ALabelTooLongForItsTileIsShortenedInsideItAtEveryWidth) {
  // The course's fixed-point lane in tiles from 24 to 640 px wide, in both columns of a row
  // (the right one ends at the canvas's edge, where a label used to be cut mid-glyph): the
  // label and its backdrop stay inside the tile, clear of its right edge, and the gutter and
  // the neighbour are untouched.
  const std::string label = "implicit_euler (fixed point)  dt = 0.0001 s";
  for (int w : {24, 40, 64, 100, 158, 200, 260, 318, 640}) {
    const int h = 90;
    const TileGrid grid(GridLayout{2, 1}, w, h);
    const Image tile = solid(w, h, kBlue);
    Image out;
    grid.compose({&tile, &tile}, {label, label}, out);
    const int scale = grid.label_scale();
    const int band = 3 * scale + text_glyph_height() * scale + 2 * scale;
    for (int i = 0; i < 2; ++i) {
      const auto [first, last] = drawn_columns(out, grid.cell_x(i), w, h, band, kBlue);
      SCOPED_TRACE("tile " + std::to_string(i) + " of width " + std::to_string(w));
      if (w >= 40) {
        EXPECT_GE(first, 0) << "a label is drawn (at least part of the name)";
      }
      if (first >= 0) {
        EXPECT_GE(first, grid.cell_x(i));
        EXPECT_LE(last, grid.cell_x(i) + w - 1 - scale) << "the label ends inside its tile";
      }
      EXPECT_EQ(pixels_not(out, grid.cell_x(i), 0, w, h - band, kBlue), 0) << "only the label's rows";
    }
    EXPECT_EQ(pixels_not(out, w, 0, grid.cell_x(1) - w, h, TilingStyle{}.background), 0) << "gutter untouched";
  }
}

TEST(TileGrid, FitsCellsIntoAnExactCanvasEvenWhenTheSizeIsOdd) {
  const TileGrid hd = TileGrid::fit(GridLayout{2, 2}, 1280, 720);
  EXPECT_EQ(hd.width(), 1280);
  EXPECT_EQ(hd.height(), 720);
  EXPECT_EQ(hd.cell_width(), 638);
  EXPECT_EQ(hd.cell_height(), 358);
  const TileGrid odd = TileGrid::fit(GridLayout{2, 2}, 161, 91);
  EXPECT_EQ(odd.width(), 161);
  EXPECT_EQ(odd.height(), 91);
  EXPECT_EQ(odd.cell_width(), 78);
  EXPECT_EQ(odd.cell_height(), 43);
  EXPECT_THROW(TileGrid::fit(GridLayout{4, 1}, 10, 10), LayoutError);
}

TEST(TileGrid, CentresASmallerTileAndCropsALargerOne) {
  const TileGrid grid(GridLayout{1, 1}, 10, 10);
  const Image small = solid(4, 4, kRed);
  Image out;
  grid.compose({&small}, {}, out);
  EXPECT_TRUE(same_rgb(out.pixel(5, 5), kRed));
  EXPECT_FALSE(same_rgb(out.pixel(1, 1), kRed));
  Image big = solid(30, 30, kGreen);
  fill_rect(big, 10, 10, 10, 10, kYellow);  // the middle third
  grid.compose({&big}, {}, out);
  EXPECT_EQ(pixels_not(out, 0, 0, 10, 10, kYellow), 0) << "the centre of the big tile is kept";
}

TEST(TileGrid, RefusesMoreTilesThanCells) {
  const TileGrid grid(GridLayout{1, 1}, 4, 4);
  const Image a = solid(4, 4, kRed);
  Image out;
  EXPECT_THROW(grid.compose({&a, &a}, {}, out), std::invalid_argument);
}

TEST(Blit, ClipsToTheDestination) {
  Image dst = solid(10, 10, kBlue);
  const Image src = solid(6, 6, kRed);
  blit(src, dst, 7, -2);
  EXPECT_TRUE(same_rgb(dst.pixel(9, 0), kRed));
  EXPECT_TRUE(same_rgb(dst.pixel(7, 3), kRed));
  EXPECT_TRUE(same_rgb(dst.pixel(6, 0), kBlue));
  EXPECT_TRUE(same_rgb(dst.pixel(7, 4), kBlue));
}

// Rows holding white label ink in one labelled tile `cell_h` rows tall: the cap height of "H".
int label_cap_height(int cell_h) {
  const TileGrid grid(GridLayout{1, 1}, cell_h * 16 / 9, cell_h);
  const Image tile = solid(cell_h * 16 / 9, cell_h, kBlue);
  Image out;
  grid.compose({&tile}, {"H"}, out);
  int rows = 0;
  for (int y = 0; y < out.height; ++y) {
    bool ink = false;
    for (int x = 0; x < out.width && !ink; ++x) ink = same_rgb(out.pixel(x, y), Rgba8{255, 255, 255, 255});
    rows += ink;
  }
  return rows;
}

TEST(TileGrid, LabelsAreAsLargeAsTheTilesOverlayTextAtTwelvePixelsOrMoreIn360RowTiles) {
  EXPECT_EQ(label_cap_height(180), 7);
  EXPECT_EQ(label_cap_height(358), 14);  // a 2x2 tile of a 1280x720 clip
  EXPECT_GE(label_cap_height(360), 12);
  EXPECT_EQ(label_cap_height(720), 28);
  EXPECT_EQ(label_cap_height(1080), 42);
  EXPECT_EQ(TileGrid(GridLayout{2, 2}, 638, 358).label_scale(), text_scale_for_height(358));
}
