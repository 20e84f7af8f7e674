#include "pd_supernodes.h"

#include <algorithm>

namespace clothsim {
namespace {

// The panel of columns [j0, j1]'s strictly lower part: its triangle and the last column's rows below.
std::int64_t panel_lower(int j0, int j1, const int* col_start) {
  const std::int64_t w = j1 - j0 + 1, below = col_start[j1 + 1] - col_start[j1];
  return w * (w - 1) / 2 + w * below;
}

// Where each supernode starts: a run grows while the next column is its last one's parent
// and the zeros it would store stay within the share.
std::vector<std::int32_t> supernode_starts(std::size_t n, const int* col_start, const int* col_row,
                                           double max_zero_share) {
  std::vector<std::int32_t> first;
  const int cols = static_cast<int>(n);
  for (int j0 = 0, j = 0; j0 < cols; j0 = ++j) {
    first.push_back(j0);
    std::int64_t entries = col_start[j + 1] - col_start[j];
    while (j + 1 < cols && col_start[j + 1] > col_start[j] && col_row[col_start[j]] == j + 1) {
      const std::int64_t with_next = entries + (col_start[j + 2] - col_start[j + 1]);
      const std::int64_t panel = panel_lower(j0, j + 1, col_start);
      if (static_cast<double>(panel - with_next) > max_zero_share * static_cast<double>(panel)) break;
      entries = with_next, ++j;
    }
  }
  first.push_back(cols);
  return first;
}

// Supernode s's rows (its columns, then its last column's rows below) and values from L.
template <typename T>
void fill_panel(BasicSupernodes<T>& f, std::size_t s, const int* col_start, const int* col_row, const double* col_value,
                std::vector<std::int32_t>& position) {
  const int j0 = f.first[s], j1 = f.first[s + 1] - 1, w = j1 - j0 + 1;
  for (int j = j0; j <= j1; ++j) f.rows.push_back(j);
  f.rows.insert(f.rows.end(), col_row + col_start[j1], col_row + col_start[j1 + 1]);
  f.row_start.push_back(static_cast<std::int32_t>(f.rows.size()));
  const std::int32_t begin = f.row_start[s], m = f.row_start[s + 1] - begin;
  for (std::int32_t i = 0; i < m; ++i) position[f.rows[begin + i]] = i;
  const std::int64_t at = f.value_start[s];
  f.value.resize(static_cast<std::size_t>(at + std::int64_t{m} * w), T(0));
  f.value_start.push_back(static_cast<std::int64_t>(f.value.size()));
  for (int k = 0; k < w; ++k)
    for (int e = col_start[j0 + k]; e < col_start[j0 + k + 1]; ++e)
      f.value[static_cast<std::size_t>(at + std::int64_t{position[col_row[e]]} * w + k)] = static_cast<T>(col_value[e]);
}

// The panels' sizes up front, so that no array grows by doubling (a peak of twice the factor).
template <typename T>
void reserve_panels(BasicSupernodes<T>& f, const int* col_start) {
  std::size_t rows = 0, values = 0;
  for (std::size_t s = 0; s < f.size(); ++s) {
    const int last = f.first[s + 1] - 1;
    const std::size_t w = static_cast<std::size_t>(f.first[s + 1] - f.first[s]);
    const std::size_t m = w + static_cast<std::size_t>(col_start[last + 1] - col_start[last]);
    rows += m, values += m * w;
  }
  f.rows.reserve(rows);
  f.value.reserve(values);
  f.row_start.reserve(f.size() + 1);
  f.value_start.reserve(f.size() + 1);
}

template <typename T>
BasicSupernodes<T> supernodes_in(std::size_t n, const int* col_start, const int* col_row, const double* col_value,
                                 const double* pivot, double max_zero_share) {
  BasicSupernodes<T> f;
  f.n = n;
  f.first = supernode_starts(n, col_start, col_row, max_zero_share);
  f.pivot.resize(n);
  for (std::size_t j = 0; j < n; ++j) f.pivot[j] = static_cast<T>(pivot[j]);
  f.entries = static_cast<std::size_t>(col_start[n]);
  reserve_panels(f, col_start);
  f.row_start.push_back(0);
  f.value_start.push_back(0);
  std::vector<std::int32_t> position(n, -1);
  for (std::size_t s = 0; s < f.size(); ++s) fill_panel(f, s, col_start, col_row, col_value, position);
  return f;
}

}  // namespace

Supernodes supernodes_of(std::size_t n, const int* col_start, const int* col_row, const double* col_value,
                         const double* pivot, double max_zero_share) {
  return supernodes_in<double>(n, col_start, col_row, col_value, pivot, max_zero_share);
}

SupernodesF supernodes_of_float(std::size_t n, const int* col_start, const int* col_row, const double* col_value,
                                const double* pivot, double max_zero_share) {
  return supernodes_in<float>(n, col_start, col_row, col_value, pivot, max_zero_share);
}

}  // namespace clothsim
