// One lane of a frame pipeline (frame_pipeline.h) on its own thread. The engine is plain C++
// and a Run touches only its own state (the Model is shared read-only), so lanes advance
// concurrently; each hands the pipeline what it needs of a target (the picture's geometry,
// metrics, positions, a field) through a small bounded queue, which keeps memory flat in clip
// length and lets a fast lane work ahead of a slow one by only a few targets.
//
// A lane that diverges stops stepping and hands over one last, frozen frame: its last finite
// state (Run::last_finite_state) at the step divergence names, with the divergence, or with
// LaneNeeds::hold_sane the state of the last target it handed over (the start before any).
// The pipeline holds that picture while other lanes go on.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "clip/common/lanes.h"
#include "clip/common/plan_parts.h"
#include "core/run/simulation.h"
#include "study/reference_cache.h"
#include "view/render_frame.h"
#include "view/render_settings.h"
#include "view/vertex_fields.h"

namespace clothsim::analysis {
class AdaptiveReference;
}  // namespace clothsim::analysis
namespace clothsim::clip {

// What the pipeline's outputs need of every target; the rest is not computed.
struct LaneNeeds {
  bool picture = false;    // the RenderFrame's geometry (make_render_frame)
  RenderDef look;          // picture: the scene's camera and what it draws
  bool metrics = false;    // FrameMetrics: energies and strain (a pass over the springs)
  bool positions = false;  // double positions, for the error field
  FieldKind field = FieldKind::None;  // strain or speed, computed on the lane's thread
  bool final_state = false;  // keep the last State (run --state)
  bool bodies = false;       // LaneFrame::bodies (--export)
  // A tile's lane: the frozen frame shows the last sane state (the last target's, or the start)
  // rather than the last finite one (frame_pipeline.h says why).
  bool hold_sane = false;
  // The reference lane: the steps (s) of the lanes it is compared with, in their order. At
  // each target it hands over, in LaneFrame::x_for, its positions at the time where a run of
  // each step lands (reference_stand.h: its own state, or interpolated between its steps),
  // so each lane is measured at its own time; only those (no picture, metrics or x), and with
  // energy_every its own energy samples, as a lane's (one run serves the error and the inset).
  std::vector<double> stand_for;
  // With stand_for: the lanes it serves, per lane (empty: all). compare --vary runs a reference
  // per value; each serves its value's lanes, the others dropped from the start (drop_lane).
  std::vector<bool> serves;
  // With stand_for: the cache it is served from when it holds this reference, and stored in
  // when it does not (reference_record.h); dir "": computed, never stored.
  analysis::ReferenceCacheSettings cache;
  double energy_every = 0.0;  // > 0: total energy sampled this often (s) between targets too,
                              // so an energy inset has a curve even in a still or a sheet
  // The reference lane on a smooth scene: > 0, the adaptive solve's tolerance
  // (study/reference.h), which serves every time exactly; the Lane's step then only sets
  // the grid of the energy samples.
  double adaptive_tolerance = 0.0;
};

// What a lane hands over at one target.
struct LaneFrame {
  double t = 0.0;
  std::int64_t step = 0;           // of the state shown
  double shown_t = 0.0;            // s, of the state shown: t, but a frozen frame's t is the divergence's
  RenderFrame frame;               // geometry only; the pipeline adds overlay, field and size
  std::vector<double> x;           // (3 x P) particle positions when LaneNeeds::positions
  // (per LaneNeeds::stand_for step) the same, at the time a run of that step stands
  std::vector<std::shared_ptr<const std::vector<double>>> x_for;
  std::vector<float> field;        // (P) when LaneNeeds::field is strain or speed
  State bodies;                    // x, v, t and step of every body when LaneNeeds::bodies
  FrameMetrics metrics;            // when LaneNeeds::metrics
  RunTotals totals;                // of the run up to here
  std::vector<std::pair<double, double>> energy;  // (t, total energy J) since the last target,
                                                  // this target's included, when energy_every
  std::optional<Divergence> divergence;  // set on the frozen frame
  bool frozen = false;             // diverged: the last finite state, and the lane's last frame
  double reference_error = 0.0;    // the reference lane: its estimated error so far, m (0 or NaN: none)
};

struct LaneResult {
  Lane spec;
  double t = 0.0;             // simulated time reached (the last target's, or divergence's)
  RunTotals totals;           // cpu_seconds: the lane thread's, not inflated by sharing cores
  std::optional<Divergence> divergence;
  std::optional<State> final_state;  // LaneNeeds::final_state, unless diverged
  // The reference lane: the adaptive one's served and check tolerances (LaneNeeds::
  // adaptive_tolerance, 0 otherwise), the fixed-step one's check step (0 otherwise), and its
  // estimated error, the largest over every time it served (m); NaN for any other lane, or
  // when the check failed.
  double adaptive_tolerance = 0.0;
  double check_tolerance = 0.0;
  double check_dt = 0.0;
  double estimated_error = std::numeric_limits<double>::quiet_NaN();
  // The reference and the cache (LaneNeeds::cache): "reused" (served from `cache_file`, its
  // totals the computation's but cpu_seconds and sim_seconds, this run's replay, the
  // computation's in computed_cpu_seconds), "stored" (computed and stored in `cache_file`),
  // "not stored: WHY", "off" (no cache), or "not cached" (a method reading settings the key
  // leaves out); "" for any other lane.
  std::string cache;
  std::string cache_file;
  double computed_cpu_seconds = std::numeric_limits<double>::quiet_NaN();
};

// Frames a lane of a frame pipeline may compute ahead of the one being shown.
inline constexpr std::size_t kLaneQueueCapacity = 4;
// What the reference (LaneNeeds::stand_for), the slowest lane, may hold to run on rather than
// wait: at most this many bytes of frames served ahead, and as many of states kept ahead.
inline constexpr double kReferenceAheadBytes = 32.0 * 1024 * 1024;
// Frames it may serve ahead: up to 32, about the first second's at 30 frames/s, so it goes on
// while the pictures of the colour scale's first second, held until then, are rendered; within
// kReferenceAheadBytes (a copy of the positions, 24 B a particle, per distinct lane step a
// frame), never fewer than a lane's.
std::size_t reference_queue_capacity(int particles, const std::vector<double>& lane_steps);

// Whether the run `started` is the run `wanted` describes (the same method, step as written and
// settings): only then may one serve in the other's place (the error's reference as the energy
// inset's, reference_lanes.h).
bool same_run(const Lane& started, const Lane& wanted);

class ReferenceRecorder;  // reference_record.h

class LaneWorker {
 public:
  // Starts the thread at once. `model` and `targets` must outlive the worker; the run steps
  // under `settings` (the lane's: lane_settings), without them the model's own. The lane stops
  // before its next step once stop() was called or `interrupt` (if given) returns true.
  LaneWorker(const Model& model, const MethodSettings& settings, Lane spec, const TargetPlan& targets,
             LaneNeeds needs, std::size_t queue_capacity = kLaneQueueCapacity, std::function<bool()> interrupt = {});
  LaneWorker(const Model& model, Lane spec, const TargetPlan& targets, LaneNeeds needs,
             std::size_t queue_capacity = kLaneQueueCapacity, std::function<bool()> interrupt = {})
      : LaneWorker(model, model.method_defaults(), std::move(spec), targets, std::move(needs), queue_capacity,
                   std::move(interrupt)) {}
  ~LaneWorker();  // stops the lane and joins
  LaneWorker(const LaneWorker&) = delete;
  LaneWorker& operator=(const LaneWorker&) = delete;

  // The frame for the next target, in order; blocks while the lane computes it, but polls
  // `interrupt` every 20 ms, so the caller is never stuck on a lane after a signal.
  // Returns false when there are no more (after a frozen one, after the last target, or
  // interrupted). Rethrows an exception the lane raised.
  bool next(LaneFrame& out);
  // Asks the lane to stop before its next step and wakes it if it waits on the queue.
  void stop();
  // The reference lane (LaneNeeds::stand_for): lane `lane` of stand_for diverged, as the frame
  // it handed over at the target the caller is about to ask this worker for says. Every earlier
  // target's positions for it were handed over already (targets go out in order); from this one
  // on they are not served, and once no live lane can need a time the reference has not passed,
  // it stops running, even in the middle of an advance (ReferenceStand::horizon).
  void drop_lane(std::size_t lane);
  const Lane& spec() const { return spec_; }
  // Waits for the thread; then result() is final.
  void join();
  LaneResult result() const;

 private:
  bool stop_asked() const;  // stop() was called, or the interrupt says so (polled between steps)
  void work();
  void push(LaneFrame frame);
  void run_targets(Run& run);
  void cached_reference(Run& run);
  bool replay_reference(const analysis::ReferenceCache& cache, const std::string& key);
  bool serve_reference(Run& run, analysis::AdaptiveReference* exact = nullptr);
  void finish_reference(const Run& run, const analysis::AdaptiveReference* exact = nullptr, const Run* check = nullptr,
                        double estimated_error = std::numeric_limits<double>::quiet_NaN());
  void set_lane_steps(std::vector<double> lane_steps);
  LaneFrame frame_of(const Run& run, const State& state) const;

  const Model& model_;
  const MethodSettings settings_;
  Lane spec_;
  const TargetPlan& targets_;
  LaneNeeds needs_;
  std::function<bool()> interrupt_;
  std::atomic<bool> stop_requested_{false};  // stop(), read by the run's per-step check
  // The reference: the lanes' steps (LaneNeeds::stand_for); lanes dropped (drop_lane), per
  // lane, and how many in all, read by its thread between steps; what it hands over, recorded
  // for the cache (push).
  const bool reference_;
  std::vector<double> lane_steps_;
  std::unique_ptr<ReferenceRecorder> recorder_;
  std::unique_ptr<std::atomic<bool>[]> dropped_;
  std::atomic<int> drops_{0};
  std::size_t capacity_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<LaneFrame> queue_;
  bool done_ = false, stop_ = false;
  std::exception_ptr error_;
  LaneResult result_;
  std::thread thread_;
};

}  // namespace clothsim::clip
