// Wrong is not ok: a lane that ran to the end with finite numbers can still be no motion of
// this cloth at all. Three stated rules, each with its bound measured on the shipped scenes
// (docs/compare.md, "When a lane is WRONG"), judged as the lane runs so its tile says so from
// the frame the evidence appears:
//   - its error against the reference exceeds kErrorFraction of the cloth's size (the
//     diagonal of its initial bounding box): it is somewhere else;
//   - the post-step projection moved particles on more than kProjectedFraction of its steps
//     (after kMinSteps) while its strain passed kStrainBound: the collision pass, not the
//     integrator, holds the cloth together, and it is crumpled;
//   - its total energy rose above E(0) by more than kEnergyRise of the scene's energy scale
//     while nothing does work on it (no kinematic sphere moves): it made energy.
#pragma once

#include <optional>
#include <string>

#include "core/model.h"
#include "core/simulation.h"

namespace clothsim::cli {

inline constexpr double kErrorFraction = 0.1;
inline constexpr double kProjectedFraction = 0.25;
inline constexpr double kStrainBound = 0.5;
inline constexpr double kEnergyRise = 0.1;
inline constexpr long kMinSteps = 100;

struct LaneEvidence {
  RunTotals totals;          // of the lane so far
  double error_max = -1.0;   // m, largest distance from the reference so far (< 0: not measured)
  double energy_rise = 0.0;  // J, largest E(t) - E(0) so far
};

// The diagonal of the cloth's initial bounding box, m.
double cloth_size(const Model& model);
// Whether something outside the cloth does work on it: a kinematic sphere that moves.
bool external_work(const Model& model);

// The first rule the evidence breaks, as the tile and the table say it ("WRONG: ..."), or
// nullopt for a plausible lane.
std::optional<std::string> implausible(const Model& model, const LaneEvidence& evidence);

}  // namespace clothsim::cli
