// Wrong is not ok: a lane that ran to the end with finite numbers can still be no motion of
// this cloth at all. Two stated rules, judged as the lane runs so its tile says so from the
// frame the evidence appears (docs/compare.md, "When a lane is WRONG"):
//   - the run's own verdict (core/diagnostics.h, the same in run, bench and converge): energy
//     made while nothing does work on the bodies, or a strain past its bound;
//   - its error against the reference exceeds kErrorFraction of the cloth's size (the
//     diagonal of its initial bounding box): it is somewhere else.
#pragma once

#include <optional>
#include <string>

#include "core/model/model.h"
#include "core/run/simulation.h"

namespace clothsim::clip {

inline constexpr double kErrorFraction = 0.1;

struct LaneEvidence {
  RunTotals totals;          // of the lane so far (totals.wrong: the run's own verdict)
  double error_max = -1.0;   // m, largest distance from the reference so far (< 0: not measured)
};

// The diagonal of the cloth's initial bounding box, m.
double cloth_size(const Model& model);

// The first rule the evidence breaks, as the tile and the table say it ("WRONG: ..."), or
// nullopt for a plausible lane.
std::optional<std::string> implausible(const Model& model, const LaneEvidence& evidence);

}  // namespace clothsim::clip
