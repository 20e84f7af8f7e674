// compare --match: which step each lane runs at, so the tiles show the trade rather than four
// methods at one step.
//
//   cost (the default): every lane free to choose (no @STEP of its own, no --dt for it) runs at
//     the step where its work per simulated second (spring-pass equivalents, core/work_units.h)
//     equals the cheapest free lane's at the scene's step. The explicit family costs a fixed
//     number of passes a step, so its step follows at once; implicit Euler's work per step
//     grows with the step, so it is measured by pilot runs over the clip's first second and
//     its step found by a secant on log cost against log step. Counted, not timed: the same
//     command chooses the same steps on every machine.
//   error TOL: every free lane at the largest step of the form 1 / (fps k) whose largest
//     particle distance from a reference run stays within TOL metres at every frame of the
//     clip, found by doubling k and then bisection (each trial stops at its first frame over TOL).
//   none: every lane at its given step or the scene's.
//
// An adaptive pair (bs3, dopri5, rkf78) given no tolerance (:tol=, :rtol=, :atol=) is matched
// on its tolerance instead, as SciML's work-precision sets match by tolerance: under cost, the
// tolerance whose pilot costs what the cheapest fixed-step lane costs (a secant on log cost
// against log tolerance); under error TOL, the loosest tolerance within TOL metres at every
// frame (tenfold down from TOL until a trial passes, then bisection on log tolerance).
// Without --match it runs at the scene's tolerance (adaptive.rtol/atol).
#pragma once

#include <string>
#include <vector>

#include "clip/common/lanes.h"
#include "core/model/model.h"

namespace clothsim::clip {

enum class MatchKind { None, Cost, Error };

struct MatchRequest {
  MatchKind kind = MatchKind::Cost;
  double tolerance = 0.0;  // m, for Error
};

// --match: {"cost"}, {"none"} or {"error", "TOL"} (TOL > 0, metres). UsageError otherwise.
MatchRequest parse_match(const std::vector<std::string>& words);

// What the clip covers, for the pilots and trials.
struct MatchClip {
  double duration = 0.0;  // s
  double fps = 30.0;
  double scene_dt = 0.0;  // s
};

// Sets the free lanes' steps (and their step_text) by `request`; returns one line per lane
// saying how its step was chosen, for the summary. `reference` is the error's reference lane
// (Error only). Lanes not free keep their step ("your step"). `lane_models` (compare --vary:
// each lane's own scene) gives per lane the model its cost is measured on; empty: `model` for
// all (Cost only: error matching has one reference, so one model).
std::vector<std::string> match_steps(const Model& model, std::vector<Lane>& lanes,
                                     const MatchRequest& request, const MatchClip& clip, const Lane& reference,
                                     const std::vector<const Model*>& lane_models = {});

// The reference `error` matching runs: `reference` at the largest step 1 / (fps K) not above
// its own, so it lands on every frame.
Lane error_reference(const Lane& reference, double fps);

// Spring-pass equivalents per simulated second of `lane` at step h over the first `window`
// seconds (up to divergence): a pilot run.
double pilot_cost(const Model& model, const Lane& lane, double h, double window);

}  // namespace clothsim::clip
