// What bench leaves besides its printed table, as the CLI and the Python module both write it:
// the CSV (study/tables/csv_tables.h), the --summary JSON (a lane per run), the plot's title,
// and a --shard part's runs journaled as they finish (study_shard.h). Printing stays with
// tools/cli/studies/cmd_bench.cpp.
#pragma once

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "clip/common/summary_json.h"
#include "clip/studies/bench_plan.h"
#include "study/study.h"
#include "study/tables/csv_tables.h"
#include "study/work_precision.h"

namespace clothsim::clip {

// The CSV's header, a result's rows (labelled by `names`), or both.
void write_bench_csv_header(std::FILE* f);
void write_bench_csv_rows(std::FILE* f, const WorkPrecisionResult& r, const LaneNames& names);
void write_bench_csv(std::FILE* f, const WorkPrecisionResult& r, const LaneNames& names);

// A run as a lane: its errors beside the common keys.
JsonObject run_lane_json(const std::string& scene, const analysis::WorkPrecisionPoint& p, const LaneNames& names);

// --summary: each run a lane, and the study's T and reference.
void write_bench_summary(const std::string& path, const std::string& source, const std::string& scene,
                         const WorkPrecisionResult& r, const LaneNames& names);

// The plot's title: the scene, T and the reference's estimated error.
std::string bench_plot_title(const std::string& name, const WorkPrecisionResult& r);

// --shard: this process's part of the runs, each journaled as it finishes (study_shard.h), the
// part's reference saved in its directory so that a rerun measures against it without running it.
int bench_shard(const BenchOptions& o, const Model& model, const WorkPrecisionSpec& spec, const LaneNames& names,
                const analysis::StudyHooks& hooks);

// The whole study's files as the CLI leaves them: --csv and --summary, each holding the runs that
// finished (atomically); then RuntimeFailure naming what stays if the study was stopped
// (interrupted() or incomplete; `runs` planned), or if its reference did not converge (no plot);
// else the plot (null: none) drawn from the CSV.
void write_bench_outputs(const BenchOptions& o, const std::string& source, const std::string& name,
                         const WorkPrecisionResult& r, const LaneNames& names, std::size_t runs, const PlotScript* plot);

// --vary: every value's rows, in order, labelled by its names ("rk4 (ks = 2e4)").
analysis::CsvTable values_table(const std::vector<ValueStudy>& studies);
// --vary's --csv and plot: as write_bench_outputs, `done` of `runs` finished, `failure` the
// first value whose reference did not converge ("" for none).
void write_values_outputs(const BenchOptions& o, const SceneDef& base, const std::vector<ValueStudy>& studies,
                          std::size_t done, std::size_t runs, const std::string& failure, const PlotScript* plot);

// --scale: the CSV's text (study/scale_study.h's columns), and its --csv and plot.
std::string scale_csv_text(const ScalePlan& plan, const std::vector<analysis::ScalePoint>& points);
void write_scale_outputs(const BenchOptions& o, const ScalePlan& plan, const std::vector<analysis::ScalePoint>& points,
                         const PlotScript* plot);

}  // namespace clothsim::clip
