// A contact sheet for reports: one row per run (integrator), one column per time, with
// row labels down the left side and column labels across the top. Cells are the same
// renders a comparison clip shows, so a sheet and a clip of one scene agree.
#pragma once

#include <string>
#include <vector>

#include "tiling.h"
#include "render/image.h"

namespace clothsim {

// A row's cells from `first_column` to its end drawn as one wide cell holding `lines`, centred
// (the first in the banner's red): a lane that diverged says so once instead of repeating its
// held picture. The cells it covers are not drawn.
struct SheetSpan {
  int row = 0;
  int first_column = 0;
  std::vector<std::string> lines;
};

// cells[r][c] is the picture of row r at column c; every row has as many cells as there
// are column labels, and there are as many rows as row labels (std::invalid_argument
// otherwise). Cells may differ in size: each sits centred in a cell of the largest size.
// With width and height (> 0) the sheet is exactly that size: cells too large to fit with
// their labels are shrunk (area average, aspect kept; never enlarged), the labels sized to
// the shrunk cells, the whole centred; too small to hold the labels: std::invalid_argument.
// `spans` (SheetSpan, at most one a row) replace the cells they cover.
Image compose_contact_sheet(const std::vector<std::vector<Image>>& cells,
                            const std::vector<std::string>& row_labels,
                            const std::vector<std::string>& column_labels,
                            const TilingStyle& style = {}, int width = 0, int height = 0,
                            const std::vector<SheetSpan>& spans = {});

// The factor (<= 1) compose_contact_sheet shrinks cells of cell_w x cell_h by to fit a sheet of
// width x height with these row labels and `columns` columns; 1 without a size.
double contact_sheet_shrink(int cell_w, int cell_h, const std::vector<std::string>& row_labels, int columns,
                            const TilingStyle& style, int width, int height);

// `src` shrunk to width x height (each no larger than src's) by averaging the source pixels
// each output pixel covers.
Image downscale(const Image& src, int width, int height);

}  // namespace clothsim
