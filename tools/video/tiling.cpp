#include "tiling.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

namespace clothsim {

namespace {

const char* kLayoutHelp = "expected COLUMNSxROWS such as 2x2, 4x1 or 1x4, or Nx1, 1xN, auto";

// "12" -> 12, "N" -> tiles, anything else -> -1.
int parse_count(std::string_view s, int tiles) {
  if (s == "N" || s == "n") return tiles;
  if (s.empty() || s.size() > 4) return -1;
  int value = 0;
  for (char c : s) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return -1;
    value = value * 10 + (c - '0');
  }
  return value;
}

}  // namespace

GridLayout parse_layout(std::string_view text, int tiles) {
  if (tiles < 1) throw LayoutError("no tiles to lay out");
  const std::string name(text);
  if (text == "auto") {
    GridLayout g;
    g.columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(tiles))));
    g.rows = (tiles + g.columns - 1) / g.columns;
    return g;
  }
  const auto x = text.find_first_of("xX");
  if (x == std::string_view::npos)
    throw LayoutError("unknown layout '" + name + "' (" + kLayoutHelp + ")");
  const int columns = parse_count(text.substr(0, x), tiles);
  const int rows = parse_count(text.substr(x + 1), tiles);
  if (columns < 1 || rows < 1)
    throw LayoutError("unknown layout '" + name + "' (" + kLayoutHelp + ")");
  const GridLayout g{columns, rows};
  const std::string count = std::to_string(tiles) + (tiles == 1 ? " tile" : " tiles");
  if (g.cells() < tiles)
    throw LayoutError("layout '" + name + "' has " + std::to_string(g.cells()) +
                      " cells for " + count);
  // Row-major filling uses ceil(tiles / columns) rows and min(tiles, columns) columns;
  // a grid with more would show a whole empty row or column.
  if ((tiles + columns - 1) / columns != rows || columns > tiles)
    throw LayoutError("layout '" + name + "' leaves a whole row or column empty for " + count);
  return g;
}

TileGrid::TileGrid(GridLayout layout, int cell_width, int cell_height, const TilingStyle& style,
                   int canvas_width, int canvas_height)
    : layout_(layout), cell_w_(cell_width), cell_h_(cell_height), style_(style) {
  if (cell_w_ < 1 || cell_h_ < 1 || layout_.columns < 1 || layout_.rows < 1 || style_.gutter < 0)
    throw LayoutError("bad tile grid: cells of " + std::to_string(cell_w_) + "x" +
                      std::to_string(cell_h_));
  const int grid_w = layout_.columns * cell_w_ + (layout_.columns - 1) * style_.gutter;
  const int grid_h = layout_.rows * cell_h_ + (layout_.rows - 1) * style_.gutter;
  canvas_w_ = std::max(grid_w, canvas_width);
  canvas_h_ = std::max(grid_h, canvas_height);
  origin_x_ = (canvas_w_ - grid_w) / 2;
  origin_y_ = (canvas_h_ - grid_h) / 2;
}

TileGrid TileGrid::fit(GridLayout layout, int width, int height, const TilingStyle& style) {
  const int cell_w = (width - (layout.columns - 1) * style.gutter) / layout.columns;
  const int cell_h = (height - (layout.rows - 1) * style.gutter) / layout.rows;
  if (cell_w < 1 || cell_h < 1)
    throw LayoutError("a " + std::to_string(layout.columns) + "x" + std::to_string(layout.rows) +
                      " grid does not fit in " + std::to_string(width) + "x" +
                      std::to_string(height) + " pixels");
  return TileGrid(layout, cell_w, cell_h, style, width, height);
}

int TileGrid::cell_x(int index) const {
  return origin_x_ + (index % layout_.columns) * (cell_w_ + style_.gutter);
}
int TileGrid::cell_y(int index) const {
  return origin_y_ + (index / layout_.columns) * (cell_h_ + style_.gutter);
}

// As the renders' own overlay text (text.h): cap height >= 1/30 of the cell height, so a
// label reads at the size of the tile's overlay: scale 1 in a 320x180 cell, 2 in a 640x360 one.
int TileGrid::label_scale() const {
  if (style_.label_scale > 0) return style_.label_scale;
  return text_scale_for_height(cell_h_);
}

void TileGrid::compose(const std::vector<const Image*>& tiles,
                       const std::vector<std::string>& labels, Image& out) const {
  if (static_cast<int>(tiles.size()) > layout_.cells())
    throw std::invalid_argument(std::to_string(tiles.size()) + " tiles for a grid of " +
                                std::to_string(layout_.cells()) + " cells");
  if (out.width != canvas_w_ || out.height != canvas_h_) out = Image(canvas_w_, canvas_h_);
  fill_rect(out, 0, 0, canvas_w_, canvas_h_, style_.background);
  // One size for every label of the grid: the largest at which the longest fits its cell
  // (a label stepping down alone would make its lane look less important than the others).
  int scale = label_scale();
  for (const std::string& label : labels)
    while (scale > 1 && !label_fits(label, cell_w_, scale)) --scale;
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    const int cx = cell_x(static_cast<int>(i)), cy = cell_y(static_cast<int>(i));
    const Image* tile = tiles[i];
    if (!tile || tile->empty()) continue;
    // Centre the tile in its cell; crop a larger one to the cell (by a sub-image copy).
    const int w = std::min(tile->width, cell_w_), h = std::min(tile->height, cell_h_);
    const int sx = (tile->width - w) / 2, sy = (tile->height - h) / 2;
    const int dx = cx + (cell_w_ - w) / 2, dy = cy + (cell_h_ - h) / 2;
    for (int y = 0; y < h; ++y)
      std::memcpy(out.pixel(dx, dy + y), tile->pixel(sx, sy + y), static_cast<std::size_t>(w) * 4);
    if (i < labels.size() && !labels[i].empty())
      draw_tile_label(out, dx, dy, w, h, labels[i], style_.label_color, scale);
  }
}

void blit(const Image& src, Image& dst, int x, int y) {
  const int x0 = std::max(0, x), y0 = std::max(0, y);
  const int x1 = std::min(dst.width, x + src.width), y1 = std::min(dst.height, y + src.height);
  if (x0 >= x1 || y0 >= y1) return;
  for (int row = y0; row < y1; ++row)
    std::memcpy(dst.pixel(x0, row), src.pixel(x0 - x, row - y),
                static_cast<std::size_t>(x1 - x0) * 4);
}

void fill_rect(Image& image, int x, int y, int w, int h, Rgba8 color) {
  const int x0 = std::max(0, x), y0 = std::max(0, y);
  const int x1 = std::min(image.width, x + w), y1 = std::min(image.height, y + h);
  for (int row = y0; row < y1; ++row)
    for (int col = x0; col < x1; ++col) std::memcpy(image.pixel(col, row), color.data(), 4);
}

bool label_fits(std::string_view label, int width, int scale) {
  // The glyphs start 3 scale in; their backdrop reaches 2 scale past them, and 1 scale of the
  // tile is left clear of it on the right.
  return text_width(label, scale) + 6 * scale <= width;
}

std::string fit_label(std::string_view label, int width, int scale) {
  if (label_fits(label, width, scale)) return std::string(label);
  const std::size_t first_word = std::min(label.find(' '), label.size());
  std::string cut;
  // The longest start of the label that fits with "..." (its trailing spaces dropped), if it
  // keeps the first word whole ...
  for (std::size_t n = label.size(); n-- > first_word;) {
    std::string head(label.substr(0, n));
    while (!head.empty() && head.back() == ' ') head.pop_back();
    if (head.size() >= first_word && label_fits(head + "...", width, scale)) return head + "...";
  }
  // ... else as much of the first word as fits: the tile is narrower than the name.
  for (std::size_t n = first_word; n-- > 0;)
    if (label_fits(std::string(label.substr(0, n)) + "...", width, scale))
      return std::string(label.substr(0, n)) + "...";
  return "";
}

void draw_tile_label(Image& image, int x, int y, int w, int h, std::string_view label,
                     Rgba8 color, int scale) {
  // A long label in a narrow tile steps down in size, then is shortened, rather than running
  // off the tile.
  while (scale > 1 && !label_fits(label, w, scale)) --scale;
  const std::string text = fit_label(label, w, scale);
  if (text.empty()) return;
  const int margin = 3 * scale;
  const int text_h = text_glyph_height() * scale;
  draw_text(image, x + margin, y + h - margin - text_h, text, color, scale, /*backdrop=*/true);
}

}  // namespace clothsim
