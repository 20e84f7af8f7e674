// Projective dynamics' factor L D L^T repacked by supernodes for its solve. A supernode is a
// run of consecutive columns j, j + 1, ... each the elimination tree's parent of the one
// before (its first entry below the diagonal is the next column); then every column's rows
// below the run lie in the last column's rows, so the run and those rows make one dense
// panel. The solve reads a panel's values contiguously, one row index per panel row rather
// than one per entry. Runs are merged while the zeros they store stay a small share of the
// panel ("relaxed" supernodes), since the grid's AMD order leaves many narrow ones. The values
// are kept in double or, where the solve only corrects a residual taken in double (projective
// dynamics' defect correction, pd_kernels.h), rounded to float: half the bytes a solve streams.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace clothsim {

template <typename T>
struct BasicSupernodes {
  std::size_t n = 0;                       // columns of L
  std::vector<std::int32_t> first;         // (S + 1) supernode s holds columns [first[s], first[s + 1])
  std::vector<std::int32_t> row_start;     // (S + 1) its panel's rows at rows[row_start[s] ...]
  std::vector<std::int32_t> rows;          // the panel's rows: its own columns, then those below, ascending
  std::vector<std::int64_t> value_start;   // (S + 1) its panel, row-major (rows x width), at value[value_start[s] ...]
  std::vector<T> value;                    // L's entries and the panels' explicit zeros (above the diagonal too)
  std::vector<T> pivot;                    // (n) D
  std::size_t entries = 0;                 // L's strictly lower entries, stored zeros excluded

  std::size_t size() const { return first.empty() ? 0 : first.size() - 1; }
};
using Supernodes = BasicSupernodes<double>;
using SupernodesF = BasicSupernodes<float>;

// A unit lower triangular L (its strictly lower entries by columns, rows ascending) and D as
// supernodes; a run is extended while the zeros its panel stores below the diagonal stay
// within `max_zero_share` of the panel's strictly lower part (0: fundamental supernodes only).
Supernodes supernodes_of(std::size_t n, const int* col_start, const int* col_row, const double* col_value,
                         const double* pivot, double max_zero_share);
// The same panels with L's values and D rounded to float.
SupernodesF supernodes_of_float(std::size_t n, const int* col_start, const int* col_row, const double* col_value,
                                const double* pivot, double max_zero_share);

}  // namespace clothsim
