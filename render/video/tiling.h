// Tiling: N pictures side by side in one frame, each labelled, for comparison clips.
//
// A layout is COLUMNSxROWS, as ffmpeg's tile filter and ImageMagick's montage spell it:
// "2x2" is a square of four, "4x1" one row of four side by side, "1x4" one column of four
// stacked. "Nx1" and "1xN" stand for one row / one column of however many tiles there are,
// and "auto" picks 1x1, 2x1, 2x2 (3-4 tiles) or the squarest grid that holds them.
// Tiles fill the grid row by row; a grid may have spare cells at the end (3 tiles in 2x2),
// never a whole empty row or column.
//
// Cells are separated by a gutter of background colour so tiles with similar edges stay
// apart. Every cell has the same size (the largest tile's); a smaller tile is centred in
// its cell. Labels are drawn with the bitmap font (render/text.h) at the bottom-left
// corner of the tile, on a dark backdrop, so they never cover a render's own top-left
// overlay text, at the size of that text (one size across the grid); a label too long for
// its tile is shortened with "..."
// (a lane's @STEP kept whole, two different labels never shortened alike), and never runs
// past the tile.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "render/image.h"
#include "render/text.h"

namespace clothsim {

struct GridLayout {
  int columns = 1, rows = 1;
  int cells() const { return columns * rows; }
};

// Thrown for a layout that is not understood or cannot hold the tiles; the message is one
// line naming the layout and what was expected.
struct LayoutError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Parses "2x2", "3x2", "1xN", "Nx1" or "auto" for `tiles` pictures (>= 1).
GridLayout parse_layout(std::string_view text, int tiles);

struct TilingStyle {
  int gutter = 4;                        // pixels between cells (and none around the grid)
  Rgba8 background{24, 24, 28, 255};     // gutters, spare cells, margins
  Rgba8 label_color{255, 255, 255, 255};
  int label_scale = 0;                   // bitmap font scale; 0: text_scale_for_height(cell height)
};

// Where each cell lies in a composed frame.
class TileGrid {
 public:
  // A grid of cells of cell_width x cell_height; the canvas is exactly the grid unless
  // canvas_width/height (>= the grid) are given, in which case the grid is centred in it.
  TileGrid(GridLayout layout, int cell_width, int cell_height, const TilingStyle& style = {},
           int canvas_width = 0, int canvas_height = 0);

  // The largest cells for which the grid fits in width x height (the gutters come out
  // of the total). Throws LayoutError when the cells would be smaller than 1 pixel.
  static TileGrid fit(GridLayout layout, int width, int height, const TilingStyle& style = {});

  int width() const { return canvas_w_; }
  int height() const { return canvas_h_; }
  int cell_width() const { return cell_w_; }
  int cell_height() const { return cell_h_; }
  const GridLayout& layout() const { return layout_; }
  int cell_x(int index) const;  // top-left corner of cell `index` (row-major)
  int cell_y(int index) const;
  int label_scale() const;
  // The text scale of `labels` in this grid: label_scale() (long labels are shortened), smaller
  // only where not even "..." of one fits its cell (1 at least).
  int label_scale(const std::vector<std::string>& labels) const;
  // `labels` as compose() draws them: each as it fits its cell at that scale (fit_labels:
  // shortened, distinct where they differ).
  std::vector<std::string> shown_labels(const std::vector<std::string>& labels) const;

  // Composes tiles[i] into cell i with labels[i] (empty label: none). Fewer tiles than
  // cells leave the rest as background; more is an error (std::invalid_argument).
  // A tile larger than the cell is cropped to it (centred). `out` is resized as needed
  // and reused from frame to frame without reallocating.
  void compose(const std::vector<const Image*>& tiles, const std::vector<std::string>& labels,
               Image& out) const;

 private:
  GridLayout layout_;
  int cell_w_, cell_h_;
  TilingStyle style_;
  int canvas_w_, canvas_h_, origin_x_, origin_y_;
};

// Copies `src` into `dst` with its top-left at (x, y), clipped to dst.
void blit(const Image& src, Image& dst, int x, int y);
// Fills the rectangle (clipped) with one colour.
void fill_rect(Image& image, int x, int y, int w, int h, Rgba8 color);
// Whether `label` fits a tile `width` pixels wide at `scale`, with its margin and backdrop
// (3 scale on the left, 1 scale clear of the right edge).
bool label_fits(std::string_view label, int width, int scale);
// `label` as it fits a tile `width` pixels wide at `scale`: itself, else cut short with "...".
// A label ending in @TAIL (a lane as --integrators spells it, "symplectic_euler@1e-4") keeps
// the tail whole and shortens the name before it ("sympl...@1e-4"), where at least one
// character of the name fits beside it; any other is cut at its end but never inside its
// first word (a lane's integrator name) unless that alone does not fit. "" when not even
// "..." fits. A label is shortened this way, never cut at the tile's edge.
std::string fit_label(std::string_view label, int width, int scale);
// The labels of one grid, each as fit_label shortens it, and no two alike that differ as
// given: labels that shorten to the same text ("impl...@1e-4" for implicit_euler@1e-4 and
// implicit_euler_fixed_point@1e-4) are cut in the middle of the name instead, keeping its
// start and its end ("imp...ler@1e-4", "imp...int@1e-4"), as wide as fit_label's and distinct
// from every other label (where the room allows: a tile a few characters wide may not).
std::vector<std::string> fit_labels(const std::vector<std::string>& labels, int width, int scale);
// Draws a label with a margin inside the tile whose top-left is (x, y) and size w x h,
// at its bottom-left corner, at `scale`, shortened (fit_label) where it does not fit; smaller
// only where not even "..." fits.
void draw_tile_label(Image& image, int x, int y, int w, int h, std::string_view label,
                     Rgba8 color, int scale);

}  // namespace clothsim
