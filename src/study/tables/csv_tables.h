// The columns of each study's CSV, said once: `bench --csv`, `stability --csv`, `converge --csv`
// (and so `merge`) write these tables, and the Python module turns the same tables into its
// DataFrames, so a column cannot be added to one front end and not the other.
// A table is built from a study's result; cells are written as io/csv_cells.h spells them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "study/convergence.h"
#include "study/stability.h"
#include "study/work_precision.h"

namespace clothsim::analysis {

// One cell: a number (shortest exact form, nan as "nan"), a whole number, or a text ("" for
// a cell left empty, e.g. diverged_at of a lane that did not diverge).
struct CsvCell {
  enum class Kind { Number, Integer, Text };
  Kind kind = Kind::Text;
  double number = 0.0;
  std::int64_t integer = 0;
  std::string text;

  static CsvCell of(double v) { return {Kind::Number, v, 0, {}}; }
  static CsvCell whole(std::int64_t v) { return {Kind::Integer, 0.0, v, {}}; }
  static CsvCell words(std::string t) { return {Kind::Text, 0.0, 0, std::move(t)}; }
  std::string spelled() const;  // as the CSV writes it (csv_cells.h)
};

struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<CsvCell>> rows;  // each of columns.size() cells

  std::string header() const;                    // "a,b,c\n"
  std::string row_text(std::size_t i) const;     // "1,x,nan\n"
  std::string text() const;                      // the header and every row
};

// bench: a row per point; `names` by WorkPrecisionPoint::lane (the lanes' stepless spellings,
// "rk4", "xpbd:10").
CsvTable work_precision_table(const WorkPrecisionResult& r, const std::vector<std::string>& names);
// stability: a row per limit; `param` the swept key as given; `names` by StabilityLimit::lane.
CsvTable stability_table(const std::vector<StabilityLimit>& limits, const StabilitySpec& spec, const std::string& param,
                         const std::vector<std::string>& names);
// converge: a row per point; `scene` the scene's name.
CsvTable convergence_table(const std::vector<ConvergencePoint>& points, const std::string& scene);

// "1/240 s: ok, 48 steps converged; 1/30 s: 3 of 6 steps not converged": a limit's frame steps.
std::string frame_steps_text(const StabilityLimit& l);

}  // namespace clothsim::analysis
