// A contact sheet for reports: one row per run (integrator), one column per time, with
// row labels down the left side and column labels across the top. Cells are the same
// renders a comparison clip shows, so a sheet and a clip of one scene agree.
#pragma once

#include <string>
#include <vector>

#include "tiling.h"
#include "render/image.h"

namespace clothsim {

// cells[r][c] is the picture of row r at column c; every row has as many cells as there
// are column labels, and there are as many rows as row labels (std::invalid_argument
// otherwise). Cells may differ in size: each sits centred in a cell of the largest size.
Image compose_contact_sheet(const std::vector<std::vector<Image>>& cells,
                            const std::vector<std::string>& row_labels,
                            const std::vector<std::string>& column_labels,
                            const TilingStyle& style = {});

}  // namespace clothsim
