// What converge leaves besides its printed table, as the CLI and the Python module both write
// it: the CSV (study/tables/csv_tables.h), the --summary JSON (a lane per method and iteration
// count, means over the states), the plot's title, and a --shard part's sweeps journaled as they
// finish (study_shard.h). Printing stays with tools/cli/studies/cmd_converge.cpp.
#pragma once

#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "clip/studies/converge_plan.h"
#include "clip/studies/study_common.h"
#include "core/model/model.h"
#include "study/convergence.h"
#include "study/study.h"

namespace clothsim::clip {

// The CSV: a row per method, state and iteration count; `scene` the scene's name.
void write_converge_csv(std::FILE* f, const std::string& scene, const std::vector<ConvergencePoint>& points);

// Per method and iteration count, the mean over the states of the RMS distance and the CPU,
// and how many of the states' steps read WRONG; keyed by (IntegratorKind as int, iterations).
struct ConvergeMean { double rms = 0.0, cpu = 0.0; int n = 0, wrong = 0; };
std::map<std::pair<int, int>, ConvergeMean> converge_means(const std::vector<ConvergencePoint>& points);

// --summary: a lane per method and iteration count, and the states and iterations asked for.
void write_converge_summary(const std::string& path, const std::string& source, const ConvergenceSpec& spec,
                            const std::vector<ConvergencePoint>& points);

// The plot's title: the scene and the step.
std::string converge_title(const Model& model, const ConvergenceSpec& spec);

// --shard: this process's part of the (state, method) sweeps, each journaled as it finishes.
int converge_shard(const ConvergeOptions& o, const Model& model, const ConvergenceSpec& spec,
                   const analysis::StudyHooks& hooks);

// The files asked for (--csv, --summary, the plot: null for none), each atomically; the plot
// drawn from the CSV. An interrupted study writes its finished sweeps without the plot.
void write_converge_outputs(const ConvergeOptions& o, const std::string& source, const Model& model,
                            const ConvergenceSpec& spec, const std::vector<ConvergencePoint>& points,
                            const PlotScript* plot);

}  // namespace clothsim::clip
