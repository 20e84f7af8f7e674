// clothsim bench SCENE --budget N [--integrators LANES] [--fps F] [--duration T] [--csv FILE]
//                                 [--plot FILE.png] [--jobs N]
//
// Substeps against iterations at equal cost (study/budget_study.h, plan in clip/studies/
// budget_plan.h): the grid's table, the reference's own error, a verdict per solver and the
// compare command that shows its grid's two ends. cmd_bench.cpp dispatches here.
#pragma once

#include "clip/studies/bench_plan.h"

namespace clothsim::cli {

int bench_budget(const clip::BenchOptions& o);

}  // namespace clothsim::cli
