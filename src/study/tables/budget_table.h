// bench --budget's CSV (docs/cli.md, "bench --budget"), said once for the CLI's --csv and the
// Python module's DataFrame, beside the other studies' tables (csv_tables.h).
#pragma once

#include <string>
#include <vector>

#include "study/budget_study.h"
#include "study/tables/csv_tables.h"

namespace clothsim::analysis {

// A row per point; `lanes` per point its lane as compare takes it ("xpbd@1/1800:1"), empty for none.
CsvTable budget_table(const BudgetResult& r, const std::vector<std::string>& lanes = {});

}  // namespace clothsim::analysis
