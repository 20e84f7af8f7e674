#include "contact_sheet.h"

#include <algorithm>
#include <stdexcept>

namespace clothsim {

Image compose_contact_sheet(const std::vector<std::vector<Image>>& cells,
                            const std::vector<std::string>& row_labels,
                            const std::vector<std::string>& column_labels,
                            const TilingStyle& style) {
  const int rows = static_cast<int>(row_labels.size());
  const int columns = static_cast<int>(column_labels.size());
  if (rows < 1 || columns < 1) throw std::invalid_argument("a contact sheet needs rows and columns");
  if (static_cast<int>(cells.size()) != rows)
    throw std::invalid_argument("contact sheet: " + std::to_string(cells.size()) + " rows of cells for " +
                                std::to_string(rows) + " row labels");
  int cell_w = 1, cell_h = 1;
  std::vector<const Image*> tiles;
  for (const auto& row : cells) {
    if (static_cast<int>(row.size()) != columns)
      throw std::invalid_argument("contact sheet: a row has " + std::to_string(row.size()) +
                                  " cells for " + std::to_string(columns) + " column labels");
    for (const Image& cell : row) {
      cell_w = std::max(cell_w, cell.width);
      cell_h = std::max(cell_h, cell.height);
      tiles.push_back(&cell);
    }
  }
  const TileGrid grid(GridLayout{columns, rows}, cell_w, cell_h, style);
  Image body;
  grid.compose(tiles, {}, body);

  // Margins sized to the labels: the longest row label on the left, one line on top.
  const int scale = grid.label_scale();
  const int pad = 4 * scale;
  const int line_h = text_glyph_height() * scale;
  int left = 0;
  for (const auto& label : row_labels) left = std::max(left, text_width(label, scale));
  left += 2 * pad;
  const int top = line_h + 2 * pad;

  Image sheet(left + body.width + pad, top + body.height + pad);
  fill_rect(sheet, 0, 0, sheet.width, sheet.height, style.background);
  blit(body, sheet, left, top);
  for (int r = 0; r < rows; ++r) {
    const int y = top + grid.cell_y(r * columns) + (cell_h - line_h) / 2;
    draw_text(sheet, pad, y, row_labels[r], style.label_color, scale, /*backdrop=*/false);
  }
  for (int c = 0; c < columns; ++c) {
    const int x = left + grid.cell_x(c) + (cell_w - text_width(column_labels[c], scale)) / 2;
    draw_text(sheet, x, pad, column_labels[c], style.label_color, scale, /*backdrop=*/false);
  }
  return sheet;
}

}  // namespace clothsim
