// What stability leaves besides its printed table, as the CLI and the Python module both write
// it: the CSV (study/tables/csv_tables.h), the --summary JSON (a lane per search), and a --shard
// part's searches journaled as they finish (study_shard.h). Printing stays with
// tools/cli/studies/cmd_stability.cpp.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "clip/common/summary_json.h"
#include "clip/studies/stability_plan.h"
#include "study/stability.h"
#include "study/study.h"

namespace clothsim::clip {

// The CSV: a row per search, `param` the swept key as given.
void write_stability_csv(std::FILE* f, const std::string& param, const std::vector<analysis::StabilityLimit>& limits,
                         const analysis::StabilitySpec& spec, const LaneNames& names);

// A search as a lane: its largest stable step as dt, the bracket, how the first unstable step
// failed, and implicit_euler's one-step-per-frame runs.
JsonObject search_lane_json(const std::string& scene, const analysis::StabilityLimit& l, const LaneNames& names);

// --summary: each search a lane, and the sweep's key, T and range.
void write_stability_summary(const std::string& path, const std::string& source, const std::string& scene,
                             const std::string& param, const std::vector<analysis::StabilityLimit>& limits,
                             const analysis::StabilitySpec& spec, const LaneNames& names, bool complete);

// --shard: this process's part of the searches, each journaled as it finishes (study_shard.h).
int stability_shard(const StabilityOptions& o, const std::string& title, const std::vector<analysis::StabilityCase>& refs,
                    const analysis::StabilitySpec& spec, const LaneNames& names, const analysis::StudyHooks& hooks);

// The whole study's files as the CLI leaves them: --csv and --summary, each holding the searches
// that finished (atomically); then RuntimeFailure naming what stays if the study was stopped
// (interrupted() or searches missing); else the plot (null: none) drawn from the CSV.
void write_stability_outputs(const StabilityOptions& o, const SceneDef& base,
                             const std::vector<analysis::StabilityLimit>& limits, const StabilityStudy& study,
                             const PlotScript* plot);

}  // namespace clothsim::clip
