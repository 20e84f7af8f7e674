// A study's CSV text as rows of cells without the named columns (the measured times, which two
// runs of the same study never share), for the *_outputs tests to compare a shard with a whole.
#pragma once

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "clip/studies/study_shard.h"

namespace clothsim::testing {

inline std::vector<std::vector<std::string>> csv_rows_without(const std::string& text,
                                                              const std::vector<std::string>& columns) {
  std::istringstream in(text);
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> keep;
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> cells = clip::csv_cells(line);
    if (rows.empty())
      for (const std::string& c : cells) keep.push_back(std::find(columns.begin(), columns.end(), c) == columns.end());
    std::vector<std::string> row;
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (i >= keep.size() || keep[i]) row.push_back(cells[i]);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace clothsim::testing
