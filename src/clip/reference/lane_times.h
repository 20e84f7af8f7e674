// Where a run lands, and positions between two of its steps: what compare's reference needs to
// stand in at each lane's own time (reference_stand.h).
//
// A Run stops at the first step at or past its target (Run::advance_to), so a lane of step h
// stands up to h past a frame's time, and lanes of different steps stand at different times.
// Between two steps of the reference the cubic Hermite interpolant through their positions
// and velocities has an error of order H^4 |x''''| for a reference step H, far below the
// methods' own where the motion is smooth; a collision inside the interval makes it first
// order in H there.
#pragma once

#include <cstdint>
#include <vector>

namespace clothsim::clip {

// The step a run of step h lands on when advanced to `target` from step `from` (Run::advance_to:
// the first step k >= from with k h >= target - 1e-6 h; its time is k h).
std::int64_t landing_step(double target, double h, std::int64_t from);

// Within 1e-9 of a step h of a step's time: where a run of step h is to be read as it stands.
// Returns the step, or -1.
std::int64_t step_at(double t, double h);

// An energy inset's samples before a target at time t, every `every` s: the times
// sample * every from the next `sample` on, below t (less 1e-9); `sample` moves past them. A
// lane and the reference standing in for the inset's (reference_stand.h) sample alike.
std::vector<double> energy_samples_before(double t, double every, long& sample);

// out = the cubic Hermite interpolant at t of positions xa (velocities va) at ta and xb (vb) at
// tb > ta, ta <= t <= tb; all of one length.
void hermite_positions(const std::vector<double>& xa, const std::vector<double>& va, double ta,
                       const std::vector<double>& xb, const std::vector<double>& vb, double tb, double t,
                       std::vector<double>& out);

}  // namespace clothsim::clip
