// The reference lane of compare's error colouring, standing in at the lanes' own times.
//
// Each lane lands on the first step at or past a target's time (Run::advance_to), so at one
// target the lanes stand at different times, up to a lane step past it. The reference runs at
// its own, smaller step and hands over its positions at each lane's time (lane_times.h: its
// own state where one of its steps lands there, else the Hermite interpolant through its two
// steps around it). A run only goes forward, so the times are served in increasing order
// across targets: a lane of a large step may stand, for an early target, past where another
// lane stands for a later one, and the reference must serve the later one first. Positions
// already served wait, shared, with their targets until every lane of the oldest is served.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <queue>
#include <vector>

#include "compare_plan.h"
#include "simulation.h"

namespace clothsim::cli {

class ReferenceStand {
 public:
  using Positions = std::shared_ptr<const std::vector<double>>;  // (3 x P) particles

  // `run` is the reference's, at its start; `lane_steps` the compared lanes' steps, in order
  // (lanes of one step share one request and one copy of the positions at each target).
  ReferenceStand(const Model& model, Run& run, const std::vector<double>& lane_steps);

  // Adds the next target (targets in time order).
  void add(const Target& target);
  bool empty() const { return pending_.empty(); }
  // Every lane's positions at the oldest target are known.
  bool front_ready() const;
  // The oldest target and its positions per lane, removed: all of them once front_ready();
  // after the run diverged, what is known (null where a lane's positions are not).
  Target pop(std::vector<Positions>& positions);
  // The earliest time some target still needs (+inf if none).
  double next_time() const;
  // Whether the next target (at t) must be added before the earliest needed time is served:
  // it may need an earlier time (a lane lands at or past its target, less Run::advance_to's
  // tolerance of 1e-6 of a step), or nothing is waiting.
  bool add_before_serving(double t) const { return empty() || t - slack_ <= next_time(); }
  // Advances the run to the earliest time needed and serves it. False when the run diverged
  // or was stopped on the way (Run::diverged(), Run::stopped()).
  bool serve_next();

 private:
  struct Slot {
    Positions x;  // null until served
  };
  struct Request {
    double t;
    std::uint64_t order;  // ties in the order asked
    std::shared_ptr<Slot> slot;
    bool operator>(const Request& o) const { return t != o.t ? t > o.t : order > o.order; }
  };
  struct Sample {
    std::int64_t step = -1;
    std::vector<double> x, v;
  };
  // The run's state at its step k (k not below the older kept sample's), kept; null on
  // divergence or a stop.
  const Sample* reach(std::int64_t k);

  const Model& model_;
  Run& run_;
  std::vector<double> steps_;                      // the lanes' distinct steps
  std::vector<std::size_t> lane_step_;             // per lane: its step's index in steps_
  std::vector<std::int64_t> landed_;               // per step: the step a run of it last landed on
  std::vector<std::shared_ptr<Slot>> last_slot_;   // per step: that landing's positions
  std::deque<std::pair<Target, std::vector<std::shared_ptr<Slot>>>> pending_;
  std::priority_queue<Request, std::vector<Request>, std::greater<Request>> requests_;
  std::uint64_t asked_ = 0;
  double slack_ = 0.0;
  Sample last_, before_;  // the run's last two kept steps
};

}  // namespace clothsim::cli
