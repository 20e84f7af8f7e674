#include "contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace clothsim {

namespace {

// The largest cell size over `cells`, after checking the shape against the labels.
void check_and_measure(const std::vector<std::vector<Image>>& cells, int rows, int columns, int& cell_w, int& cell_h) {
  if (rows < 1 || columns < 1) throw std::invalid_argument("a contact sheet needs rows and columns");
  if (static_cast<int>(cells.size()) != rows)
    throw std::invalid_argument("contact sheet: " + std::to_string(cells.size()) + " rows of cells for " +
                                std::to_string(rows) + " row labels");
  cell_w = cell_h = 1;
  for (const auto& row : cells) {
    if (static_cast<int>(row.size()) != columns)
      throw std::invalid_argument("contact sheet: a row has " + std::to_string(row.size()) +
                                  " cells for " + std::to_string(columns) + " column labels");
    for (const Image& cell : row) cell_w = std::max(cell_w, cell.width), cell_h = std::max(cell_h, cell.height);
  }
}

// The label margins of a sheet whose cells are `cell_h` high: the longest row label on the
// left, one line on top, `pad` right and below.
struct Margins {
  int scale, pad, left, top;
};
Margins margins_for(const std::vector<std::string>& row_labels, int cell_h, const TilingStyle& style) {
  Margins m;
  m.scale = style.label_scale > 0 ? style.label_scale : text_scale_for_height(cell_h);
  m.pad = 4 * m.scale;
  m.left = 0;
  for (const auto& label : row_labels) m.left = std::max(m.left, text_width(label, m.scale));
  m.left += 2 * m.pad;
  m.top = text_glyph_height() * m.scale + 2 * m.pad;
  return m;
}

// `line` broken at spaces into pieces at most `width` pixels wide at `scale` (a word wider
// than that stays whole).
std::vector<std::string> wrap_words(const std::string& line, int width, int scale) {
  std::vector<std::string> out;
  std::string piece;
  std::size_t at = 0;
  while (at <= line.size()) {
    const std::size_t end = std::min(line.find(' ', at), line.size());
    const std::string word = line.substr(at, end - at);
    const std::string longer = piece.empty() ? word : piece + " " + word;
    if (!piece.empty() && text_width(longer, scale) > width) {
      out.push_back(piece);
      piece = word;
    } else {
      piece = longer;
    }
    at = end + 1;
  }
  if (!piece.empty()) out.push_back(piece);
  return out;
}

// Span `s` drawn over the grid `body`: one cell from its first column to the row's end, its
// lines centred at the largest scale up to `scale` at which the widest fits, else at scale 1
// broken at spaces (what still does not fit is clipped at the cell's edges).
void draw_span(Image& body, const TileGrid& grid, int columns, const SheetSpan& s, const TilingStyle& style,
               int scale) {
  const int first = s.row * columns + s.first_column, last = s.row * columns + columns - 1;
  const int x0 = grid.cell_x(first), y0 = grid.cell_y(first);
  const int w = grid.cell_x(last) + grid.cell_width() - x0, h = grid.cell_height();
  Image cell(w, h);  // drawn apart, so nothing runs past the cell
  fill_rect(cell, 0, 0, w, h, {44, 44, 50, 255});  // a panel a shade off the gutters
  int widest = 0;
  for (const std::string& line : s.lines) widest = std::max(widest, text_width(line, 1));
  while (scale > 1 && widest * scale > w - 8 * scale) --scale;
  std::vector<std::pair<std::string, bool>> lines;  // (text, the first line's: red)
  for (std::size_t k = 0; k < s.lines.size(); ++k)
    for (const std::string& piece : wrap_words(s.lines[k], w - 8 * scale, scale)) lines.emplace_back(piece, k == 0);
  const int line_h = text_glyph_height() * scale * 3 / 2;
  const int top = std::max(0, (h - line_h * static_cast<int>(lines.size())) / 2);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const Rgba8 color = lines[k].second ? Rgba8{255, 72, 60, 255} : style.label_color;  // the banner's red
    draw_text(cell, (w - text_width(lines[k].first, scale)) / 2, top + static_cast<int>(k) * line_h, lines[k].first,
              color, scale, /*backdrop=*/false);
  }
  blit(cell, body, x0, y0);
}

}  // namespace

Image downscale(const Image& src, int width, int height) {
  Image out(width, height);
  const double fx = static_cast<double>(src.width) / width, fy = static_cast<double>(src.height) / height;
  for (int y = 0; y < height; ++y) {
    const int y0 = static_cast<int>(y * fy), y1 = std::max(y0 + 1, static_cast<int>((y + 1) * fy));
    for (int x = 0; x < width; ++x) {
      const int x0 = static_cast<int>(x * fx), x1 = std::max(x0 + 1, static_cast<int>((x + 1) * fx));
      int sum[4] = {0, 0, 0, 0};
      for (int sy = y0; sy < std::min(y1, src.height); ++sy)
        for (int sx = x0; sx < std::min(x1, src.width); ++sx)
          for (int c = 0; c < 4; ++c) sum[c] += src.pixel(sx, sy)[c];
      const int n = (std::min(y1, src.height) - y0) * (std::min(x1, src.width) - x0);
      for (int c = 0; c < 4; ++c) out.pixel(x, y)[c] = static_cast<std::uint8_t>((sum[c] + n / 2) / n);
    }
  }
  return out;
}

double contact_sheet_shrink(int cell_w, int cell_h, const std::vector<std::string>& row_labels, int columns,
                            const TilingStyle& style, int width, int height) {
  if (width <= 0 || height <= 0) return 1.0;
  const int rows = static_cast<int>(row_labels.size());
  // The margins follow the cells' size (their text scale), so a few rounds settle it.
  double f = 1.0;
  for (int round = 0; round < 4; ++round) {
    const Margins m = margins_for(row_labels, std::max(1, static_cast<int>(cell_h * f)), style);
    const double room_w = width - m.left - m.pad - (columns - 1) * style.gutter;
    const double room_h = height - m.top - m.pad - (rows - 1) * style.gutter;
    f = std::min({1.0, room_w / (columns * cell_w), room_h / (rows * cell_h)});
  }
  if (static_cast<int>(cell_w * f) < 1 || static_cast<int>(cell_h * f) < 1)
    throw std::invalid_argument("contact sheet: " + std::to_string(width) + "x" + std::to_string(height) +
                                " pixels cannot hold its labels and cells");
  return f;
}

Image compose_contact_sheet(const std::vector<std::vector<Image>>& cells_in,
                            const std::vector<std::string>& row_labels,
                            const std::vector<std::string>& column_labels,
                            const TilingStyle& style, int width, int height,
                            const std::vector<SheetSpan>& spans) {
  const int rows = static_cast<int>(row_labels.size());
  const int columns = static_cast<int>(column_labels.size());
  int cell_w = 1, cell_h = 1;
  check_and_measure(cells_in, rows, columns, cell_w, cell_h);

  std::vector<std::vector<Image>> fitted;  // the cells shrunk to fit width x height
  const std::vector<std::vector<Image>>* cells = &cells_in;
  const double f = contact_sheet_shrink(cell_w, cell_h, row_labels, columns, style, width, height);
  if (f < 1.0) {
    for (const auto& row : cells_in) {
      fitted.emplace_back();
      for (const Image& cell : row)
        fitted.back().push_back(downscale(cell, std::max(1, static_cast<int>(cell.width * f)),
                                          std::max(1, static_cast<int>(cell.height * f))));
    }
    cells = &fitted;
    check_and_measure(fitted, rows, columns, cell_w, cell_h);
  }
  std::vector<const Image*> tiles;
  for (const auto& row : *cells)
    for (const Image& cell : row) tiles.push_back(&cell);
  const TileGrid grid(GridLayout{columns, rows}, cell_w, cell_h, style);
  Image body;
  grid.compose(tiles, {}, body);

  const Margins m = margins_for(row_labels, cell_h, style);
  for (const SheetSpan& s : spans) {
    if (s.row < 0 || s.row >= rows || s.first_column < 0 || s.first_column >= columns)
      throw std::invalid_argument("contact sheet: a span outside the grid");
    draw_span(body, grid, columns, s, style, m.scale);
  }
  const int natural_w = m.left + body.width + m.pad, natural_h = m.top + body.height + m.pad;
  const int sheet_w = width > 0 ? std::max(width, natural_w) : natural_w;
  const int sheet_h = height > 0 ? std::max(height, natural_h) : natural_h;
  const int ox = (sheet_w - natural_w) / 2, oy = (sheet_h - natural_h) / 2;  // centred in the asked size
  Image sheet(sheet_w, sheet_h);
  fill_rect(sheet, 0, 0, sheet.width, sheet.height, style.background);
  blit(body, sheet, ox + m.left, oy + m.top);
  const int line_h = text_glyph_height() * m.scale;
  for (int r = 0; r < rows; ++r) {
    const int y = oy + m.top + grid.cell_y(r * columns) + (cell_h - line_h) / 2;
    draw_text(sheet, ox + m.pad, y, row_labels[r], style.label_color, m.scale, /*backdrop=*/false);
  }
  for (int c = 0; c < columns; ++c) {
    const int x = ox + m.left + grid.cell_x(c) + (cell_w - text_width(column_labels[c], m.scale)) / 2;
    draw_text(sheet, x, oy + m.pad, column_labels[c], style.label_color, m.scale, /*backdrop=*/false);
  }
  return sheet;
}

}  // namespace clothsim
