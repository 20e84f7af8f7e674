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
//
// A lane that diverged needs nothing more (drop_lane): the reference stops serving it, so a lane
// of a huge step that blew up on its first step (rk4@20 on a 0.5 s clip asked for t = 20 s)
// does not keep it running. horizon() is the latest time a lane still live can need, the last
// target's landing time for the largest live step: from the moment it knows of a lane's
// divergence (the pipeline drops the lane when its frozen frame arrives), the reference never
// runs past it by more than one of its own steps (LaneWorker's stop check stops its run there,
// in the middle of an advance if need be).
//
// With an energy inset it also samples its own total energy as a lane does (LaneNeeds::
// energy_every), served in the same time order: one run is both the error's reference and the
// inset's.
//
// On a smooth scene the reference is the adaptive solve (study/reference.h, serve_exactly):
// every time is then served exactly, by the solve's dense output, with no Hermite between
// steps; `run` then only sets the grid the energy samples fall on (its dt) and is never stepped.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "clip/common/plan_parts.h"
#include "core/run/simulation.h"
#include "study/reference.h"

namespace clothsim::clip {

class ReferenceStand {
 public:
  using Positions = std::shared_ptr<const std::vector<double>>;  // (3 x P) particles

  // `run` is the reference's, at its start; `lane_steps` the compared lanes' steps, in order
  // (0 for a lane that lands on every target exactly: an adaptive pair, Lane::landing_grid)
  // (lanes of one step share one request and one copy of the positions at each target);
  // `last_t` the last target's time (TargetPlan::last_time). `run` must outlive the stand.
  ReferenceStand(const Model& model, Run& run, const std::vector<double>& lane_steps, double last_t);

  // Serves every time from `exact` (advanced in increasing time) rather than from `run`. Before
  // the first add(); `exact` must outlive the stand.
  void serve_exactly(analysis::AdaptiveReference& exact) { exact_ = &exact; }
  // Checks the fixed-step run (not an exact one) against `check`, a run of the same method at
  // twice its step from the same start: at every even step the stand keeps, `check` is advanced
  // there and the largest particle distance between the two raises estimated_error(). For a
  // reference whose error is first order in its step (projected contacts), that distance is
  // its error; where it converges faster, more. Before the first add(); outlives the stand.
  void check_against(Run& check) { check_ = &check; }
  // m, the check's largest distance so far; NaN without a check, or once the check diverged
  // or stopped short (no estimate then).
  double estimated_error() const { return estimated_error_; }
  // Also serves the run's total energy (J) every `every` seconds between targets and at each
  // target, at the states where a run of its own advanced to those times stands, as
  // LaneWorker's energy samples of a lane are. Before the first add().
  void sample_energy(double every);
  // Adds the next target (targets in time order).
  void add(const Target& target);
  bool empty() const { return pending_.empty(); }
  // Every live lane's positions at the oldest target, and its energy samples, are known.
  bool front_ready() const;
  // The oldest target and its positions per lane, removed: all of them once front_ready();
  // after the run diverged or stopped, what is known (null where a lane's positions are not,
  // and for a dropped lane whose were not served before it was dropped). With sample_energy,
  // its (t, total energy J) samples since the previous target, this one's included, in `energy`.
  Target pop(std::vector<Positions>& positions, std::vector<std::pair<double, double>>* energy = nullptr);
  // The earliest time some target still needs (+inf if none).
  double next_time() const;
  // Lane `lane` diverged: its times still to serve are not served, and the targets wait for
  // it no longer. May be called while serve_next() is running the reference (from its stop check).
  void drop_lane(std::size_t lane);
  // The latest time a live lane can still need: the last target's landing for the largest live
  // step (-inf when every lane was dropped). Every request of a live lane is at or before it.
  double horizon() const { return horizon_; }
  // Positions (3 x P doubles each) the waiting targets hold now, each shared copy once.
  std::size_t positions_held() const;
  // The most targets waiting at once for lanes of `lane_steps` over `plan`'s targets: those
  // within the largest step (and add_before_serving's slack) of the oldest, at the plan's frame
  // rate, plus its targets off the frames (sheet columns, a still), never more than the plan.
  // At most one copy of the positions per distinct step each (compare's memory estimate).
  static long waiting_bound(const std::vector<double>& lane_steps, const TargetPlan& plan);
  // Whether the next target (at t) must be added before the earliest needed time is served:
  // it may need an earlier time (a lane lands at or past its target, less Run::advance_to's
  // tolerance of 1e-6 of a step), or nothing is waiting.
  // With sample_energy, t is the earlier of the next target's and its first energy sample's.
  bool add_before_serving(double t) const {
    return empty() || std::min(t, next_energy_time()) - slack_ <= next_time();
  }
  // Advances the run to the earliest time needed and serves it. False when the run diverged
  // or was stopped on the way (Run::diverged(), Run::stopped()).
  bool serve_next();

 private:
  struct Slot {
    Positions x;  // null until served
  };
  struct EnergySlot {
    bool served = false;
    double t = 0.0, e = 0.0;  // s, J
  };
  struct Request {
    double t;
    std::uint64_t order;  // ties in the order asked
    std::size_t step;     // index in steps_ (an energy sample: steps_.size())
    std::shared_ptr<Slot> slot;
    std::shared_ptr<EnergySlot> energy;  // an energy sample at the run's own step k
    std::int64_t k = -1;
    bool operator<(const Request& o) const { return t != o.t ? t < o.t : order < o.order; }
  };
  struct Sample {
    std::int64_t step = -1;
    double t = 0.0;
    std::vector<double> x, v;
    double energy = 0.0;  // total, J (with sample_energy)
  };
  // The run's state at its step k (k not below the older kept sample's), kept; null on
  // divergence or a stop.
  const Sample* reach(std::int64_t k);
  void keep_sample(const State& state);
  void compare_with_check(const State& state);  // check_ to the even step state is at
  const Sample* reach_exactly(double t, std::int64_t k);  // exact_ at time t (its step k, or -1)
  void update_horizon();
  std::shared_ptr<EnergySlot> ask_energy(double t);
  double next_energy_time() const;  // +inf without sample_energy

  const Model& model_;
  Run& run_;
  analysis::AdaptiveReference* exact_ = nullptr;
  Run* check_ = nullptr;
  double estimated_error_ = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> steps_;                      // the lanes' distinct steps
  std::vector<std::size_t> lane_step_;             // per lane: its step's index in steps_
  std::vector<std::int64_t> landed_;               // per step: the step a run of it last landed on
  std::vector<std::shared_ptr<Slot>> last_slot_;   // per step: that landing's positions
  std::vector<double> last_needed_;                // per step: its landing time for the last target
  std::vector<bool> live_;                         // per lane: not dropped
  std::vector<int> live_lanes_;                    // per step: its lanes not dropped
  std::deque<std::pair<Target, std::vector<std::shared_ptr<Slot>>>> pending_;  // per lane a slot
  std::set<Request> requests_;                     // of live steps only, earliest first
  std::uint64_t asked_ = 0;
  double slack_ = 0.0;
  double horizon_ = 0.0;
  Sample last_, before_;  // the run's last two kept steps
  // sample_energy: the interval, the next sample's index, the run's own landing step and the
  // last sample asked (a sample where the run did not step shares it), and per waiting target
  // its samples.
  double energy_every_ = 0.0, own_last_needed_ = 0.0, last_t_ = 0.0;
  long sample_ = 0;
  std::int64_t own_landed_ = 0;
  std::shared_ptr<EnergySlot> last_energy_;
  std::deque<std::vector<std::shared_ptr<EnergySlot>>> pending_energy_;
};

// The reference lane's positions at the lanes' times (the stand above), for lanes of
// `lane_steps` over `plan`'s targets: its last two steps kept (positions and velocities), and a
// copy of the positions per distinct lane step for every target waiting for a lane of a larger
// step (ReferenceStand::waiting_bound: a lane of 20 s on a 30 frames/s clip holds every frame
// of those 20 s) or handed over and not yet measured (the worker's queue of `queue` frames, one
// being pushed, the pipeline's). 24 B per particle a copy.
double reference_positions_bytes(const SceneDef& scene, const std::vector<double>& lane_steps,
                                 const TargetPlan& plan, std::size_t queue);

}  // namespace clothsim::clip
