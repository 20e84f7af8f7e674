// The states a reference run passed before it knew the lanes' steps.
//
// compare --match cost chooses some lanes' steps by pilot runs, while the reference's own step
// is known at once; so the reference starts at t = 0 beside the pilots (LaneWorker, with
// LaneNeeds::stand_for_later) and cannot yet say which times the lanes will stand at. It keeps
// its state a little before each target's time (keep_step); once the steps are known,
// ReferenceStand reaches a time the run has passed by replaying from the latest state kept at
// or before it. A step is a function of the State alone (core/simulation.h), so a replayed
// state is the run's own to the bit; a replay costs the steps from that state to the time, a
// lane step or less.
#pragma once

#include <cstdint>
#include <deque>

#include "core/run/simulation.h"

namespace clothsim::clip {

class ReferenceHistory {
 public:
  // `model`, `settings`, `kind` and `dt`: the reference run's (a replay takes its steps).
  // `model` must outlive the history.
  ReferenceHistory(const Model& model, const MethodSettings& settings, IntegratorKind kind, double dt);
  ReferenceHistory(const Model& model, IntegratorKind kind, double dt)
      : ReferenceHistory(model, model.method_defaults(), kind, dt) {}

  // The step to keep for a target at time t: a little before any step a lane's time at or
  // after t (less Run::advance_to's tolerance and a rounding) reads.
  static std::int64_t keep_step(double t, double dt);

  // Keeps the run's state (steps increasing).
  void keep(const State& state);
  bool empty() const { return kept_.empty(); }
  std::size_t size() const { return kept_.size(); }
  std::int64_t first_step() const { return kept_.empty() ? -1 : kept_.front().step; }

  // The run's state at step k (k at or after first_step()), replayed from the latest state kept
  // at or before it. Asked in increasing k (as ReferenceStand serves times) it continues its
  // replay rather than restarting, and forgets the kept states before the one it starts from.
  const State& at(std::int64_t k);
  double replay_cpu_seconds() const { return replay_cpu_; }  // this thread's CPU spent in at()

 private:
  const Model& model_;
  MethodSettings settings_;
  IntegratorKind kind_;
  double dt_;
  std::deque<State> kept_;  // steps increasing
  State replay_;
  bool replaying_ = false;  // replay_ is a kept state stepped on, not yet restarted
  Workspace ws_;
  double replay_cpu_ = 0.0;
};

}  // namespace clothsim::clip
