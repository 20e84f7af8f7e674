// What `clothsim compare` says when its lanes have run: the table on stdout (one row per lane
// and the reference's, with the work in spring-pass equivalents beside the CPU time, and a
// result that says DIVERGED, NOT CONVERGED, WRONG or ok), how each lane's step was chosen
// (--match), each lane's colouring field in numbers, and the same in --summary's JSON.
#pragma once

#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "clip/common/summary_json.h"
#include "clip/frames/frame_pipeline.h"
#include "core/model/model.h"

namespace clothsim {
class TileGrid;
}

namespace clothsim::clip {

// What the summary shows beside the pipeline's report.
struct SummaryContext {
  std::vector<std::string> names;        // per lane: its row's name ("rk4", "ks = 2e4 rk4")
  std::vector<std::string> step_choice;  // per lane: how its step was chosen (--match)
};

// The result column: DIVERGED at ..., NOT CONVERGED ..., WRONG: ... or ok to t = ...
std::string lane_result(const LaneResult& r, const std::string& wrong);

void print_summary(const Model& model, const PipelineReport& report, FieldKind color, const SummaryContext& context);

// stderr's last line: where the wall time went (simulate, render, each output).
void print_breakdown(const TileGrid& grid, int legend_width, const PipelineReport& report, double wall);

// A lane's error is unresolved when its largest is under this times the reference's estimated
// error (LaneResult::estimated_error): the reference cannot tell it, so no number is given. A
// lane that diverged is not: its error before the blow-up is no result (it says diverged).
// (kUnresolvedFactor: frame_pipeline.h, whose tiles say UNRESOLVED by the same rule.)
bool lane_unresolved(const PipelineReport& report, std::size_t lane, FieldKind color);

// --summary's "reference" (or under --vary one of "references", with "for": the value): its
// method, step or tolerance, and estimated_error_m (the largest over the measured frames; null
// where not estimated).
JsonObject summary_reference(const ReferenceReport& reference);
// Whether a reference was computed or reused from the cache, and where it is: the text after
// "reference: " of the table's line (LaneResult::cache; "" for a lane that is no reference).
std::string reference_cache_text(const LaneResult& reference);

// --summary's lanes: the pipeline's report as JSON objects (docs/summary.md), the reference last.
std::vector<JsonObject> summary_lanes(const Model& model, const PipelineReport& report, FieldKind color,
                                      const SummaryContext& context);

}  // namespace clothsim::clip
