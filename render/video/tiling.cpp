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

int TileGrid::label_scale(const std::vector<std::string>& labels) const {
  // One size for all text of the grid, the tiles' overlay's: a label too long for its cell is
  // shortened (fit_labels), never drawn smaller than the time beside it. Smaller only where
  // not even "..." fits at that size.
  int scale = label_scale();
  for (const std::string& label : labels)
    while (scale > 1 && !label.empty() && fit_label(label, cell_w_, scale).empty()) --scale;
  return scale;
}

std::vector<std::string> TileGrid::shown_labels(const std::vector<std::string>& labels) const {
  return fit_labels(labels, cell_w_, label_scale(labels));
}

void TileGrid::compose(const std::vector<const Image*>& tiles,
                       const std::vector<std::string>& labels, Image& out) const {
  if (static_cast<int>(tiles.size()) > layout_.cells())
    throw std::invalid_argument(std::to_string(tiles.size()) + " tiles for a grid of " +
                                std::to_string(layout_.cells()) + " cells");
  if (out.width != canvas_w_ || out.height != canvas_h_) out = Image(canvas_w_, canvas_h_);
  fill_rect(out, 0, 0, canvas_w_, canvas_h_, style_.background);
  const int scale = label_scale(labels);
  const std::vector<std::string> shown = shown_labels(labels);
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
    if (i < shown.size() && !shown[i].empty())
      draw_tile_label(out, dx, dy, w, h, shown[i], style_.label_color, scale);
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

namespace {

// Where the part of a label that shortening keeps whole starts: its last '@', with a name
// before it and no space after it (a lane as --integrators spells it: the "@1e-4" of
// "rk4@1e-4"); else the label's end (nothing kept whole).
std::size_t kept_tail(std::string_view label) {
  const std::size_t at = label.rfind('@');
  if (at == std::string_view::npos || at == 0 || at + 1 == label.size() ||
      label.find(' ', at) != std::string_view::npos)
    return label.size();
  return at;
}

// A start of a label without what a cut leaves dangling before "..." ("implicit_euler_").
std::string without_dangling(std::string_view head) {
  while (!head.empty() && (head.back() == ' ' || head.back() == '_' || head.back() == '('))
    head.remove_suffix(1);
  return std::string(head);
}

// How many characters of a name `name_size` long fit before "..." and `tail` (0: none).
// The font is monospaced: how many, not which.
std::size_t name_room(std::size_t name_size, std::string_view tail, int width, int scale) {
  for (std::size_t n = name_size; n > 0; --n)
    if (label_fits(std::string(n, 'x') + "..." + std::string(tail), width, scale)) return n;
  return 0;
}

// Where a label's name ends (at its kept tail, else the label's end), how many characters of
// it fit with "..." for a cut in the middle, and whether the tail is kept beside them: where
// there is room for at least 2 (a start and an end), else the tail is dropped (as fit_label
// drops it: the tile is narrower than a name and a step).
struct NameRoom {
  std::size_t at = 0, room = 0;
  bool tail = false;
};
NameRoom name_room_of(std::string_view label, int width, int scale) {
  if (label.empty()) return {};
  NameRoom r{kept_tail(label), 0, false};
  if (r.at < label.size()) {
    r.room = name_room(r.at - 1, label.substr(r.at), width, scale);
    r.tail = r.room >= 2;
  }
  if (!r.tail) r.room = name_room(r.at - 1, {}, width, scale);
  return r;
}

// `label` shortened in the middle of its name, keeping the name's last `end` characters and
// its kept tail where it fits ("sym...ler@1e-4"); "" where the room has no place for them and
// a start.
std::string cut_in_middle(std::string_view label, std::size_t end, int width, int scale) {
  const NameRoom r = name_room_of(label, width, scale);
  if (end + 1 > r.room || end >= r.at) return "";
  const std::string head = without_dangling(label.substr(0, r.room - end));
  if (head.empty()) return "";
  return head + "..." + std::string(label.substr(r.at - end, end)) + std::string(r.tail ? label.substr(r.at) : "");
}

// "..." and as much of the end of `label` as fits with it ("...@1e-4"); "" for none of it.
std::string end_of(std::string_view label, int width, int scale) {
  for (std::size_t n = label.size(); n-- > 1;)
    if (label_fits("..." + std::string(label.substr(label.size() - n)), width, scale))
      return "..." + std::string(label.substr(label.size() - n));
  return "";
}

}  // namespace

std::string fit_label(std::string_view label, int width, int scale) {
  if (label_fits(label, width, scale)) return std::string(label);
  // A lane's step stays whole and its name is shortened before it ("sympl...@1e-4"): two
  // lanes of one integrator differ only there.
  const std::size_t at = kept_tail(label);
  if (at < label.size())
    for (std::size_t n = at; n-- > 1;) {
      const std::string cut = without_dangling(label.substr(0, n));
      if (!cut.empty() && label_fits(cut + "..." + std::string(label.substr(at)), width, scale))
        return cut + "..." + std::string(label.substr(at));
    }
  const std::size_t first_word = std::min(label.find(' '), label.size());
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

std::vector<std::string> fit_labels(const std::vector<std::string>& labels, int width, int scale) {
  std::vector<std::string> out;
  for (const std::string& label : labels) out.push_back(fit_label(label, width, scale));
  std::vector<bool> settled(out.size(), false);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (settled[i] || out[i] == labels[i]) continue;
    // The labels shortened to this same text, and whether any two of them differ.
    std::vector<std::size_t> same;
    bool differ = false;
    for (std::size_t j = i; j < out.size(); ++j)
      if (out[j] == out[i] && out[j] != labels[j]) {
        same.push_back(j);
        differ = differ || labels[j] != labels[i];
        settled[j] = true;
      }
    if (!differ) continue;
    // Cut them in the middle instead, keeping as much of the name's end as of its start first
    // ("imp...ler@1e-4", "imp...int@1e-4"), then more of the end, then less: the first split
    // that tells every one apart from the others and from the rest of the grid, the same for all.
    const std::size_t room = name_room_of(labels[i], width, scale).room, half = std::max<std::size_t>(room / 2, 1);
    std::vector<std::size_t> ends;
    for (std::size_t e = half; e < room; ++e) ends.push_back(e);
    for (std::size_t e = half; e-- > 1;) ends.push_back(e);
    // Last, for a tile too narrow for a letter of the name beside the step: the end alone
    // ("...@1e-4").
    ends.push_back(0);
    for (std::size_t end : ends) {
      std::vector<std::string> cut;
      bool ok = true;
      for (std::size_t j : same) {
        cut.push_back(end > 0 ? cut_in_middle(labels[j], end, width, scale) : end_of(labels[j], width, scale));
        ok = ok && !cut.back().empty();
      }
      for (std::size_t a = 0; ok && a < same.size(); ++a) {
        for (std::size_t b = a + 1; ok && b < same.size(); ++b)
          ok = cut[a] != cut[b] || labels[same[a]] == labels[same[b]];
        for (std::size_t m = 0; ok && m < out.size(); ++m)
          ok = std::find(same.begin(), same.end(), m) != same.end() || out[m] != cut[a];
      }
      if (!ok) continue;
      for (std::size_t a = 0; a < same.size(); ++a) out[same[a]] = cut[a];
      break;
    }
  }
  return out;
}

void draw_tile_label(Image& image, int x, int y, int w, int h, std::string_view label,
                     Rgba8 color, int scale) {
  // A long label in a narrow tile is shortened at the given size (the grid's one text size),
  // smaller only where not even "..." fits.
  while (scale > 1 && fit_label(label, w, scale).empty()) --scale;
  const std::string text = fit_label(label, w, scale);
  if (text.empty()) return;
  const int margin = 3 * scale;
  const int text_h = text_glyph_height() * scale;
  draw_text(image, x + margin, y + h - margin - text_h, text, color, scale, /*backdrop=*/true);
}

}  // namespace clothsim
