// One run of a comparison on its own thread. The engine is plain C++ and a Run touches
// only its own state (the Model is shared read-only), so N runs advance concurrently;
// each hands the renderer a snapshot per target through a small bounded queue, which
// keeps memory flat in clip length and lets a fast run work ahead of a slow one by only
// a few frames.
//
// A run that diverges stops stepping and hands over its last good frame once more, with
// the banner "DIVERGED at t = ..." and the reason: the tile freezes there while the
// other runs go on.
#pragma once

#include <condition_variable>
#include <deque>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "compare_plan.h"
#include "render_frame.h"
#include "simulation.h"

namespace clothsim::cli {

struct TileSnapshot {
  RenderFrame frame;    // sized to the tile, overlay text included
  bool frozen = false;  // the run diverged: its last good frame with the banner; the last snapshot
};

struct RunSummary {
  IntegratorKind kind{};
  double dt = 0.0;
  double t = 0.0;             // simulated time reached (the last good state's when diverged)
  RunTotals totals;           // cpu_seconds: the stepping thread's, not inflated by sharing cores
  std::optional<Divergence> divergence;
};

class RunWorker {
 public:
  // Starts the thread at once. `targets` and `model` must outlive the worker. The run stops
  // before its next step once stop() was called or `interrupt` (if given) returns true.
  RunWorker(const Model& model, IntegratorKind kind, double dt, const TargetPlan& targets,
            int tile_width, int tile_height, std::size_t queue_capacity = 4,
            std::function<bool()> interrupt = {});
  ~RunWorker();  // stops the run and joins
  RunWorker(const RunWorker&) = delete;
  RunWorker& operator=(const RunWorker&) = delete;

  // The snapshot for the next target, in order; blocks while the run computes it, but polls
  // `interrupt` every 20 ms, so the caller is never stuck on a lane after a signal.
  // Returns false when there are no more (after a frozen one, after the last target, or
  // interrupted). Rethrows an exception the run raised.
  bool next(TileSnapshot& out);
  // Asks the run to stop at the next target and wakes it if it waits on the queue.
  void stop();
  // Waits for the thread; then summary() is final.
  void join();
  RunSummary summary() const;

 private:
  void work();
  void push(TileSnapshot snapshot);
  RenderFrame snapshot_of(const Run& run) const;

  const Model& model_;
  IntegratorKind kind_;
  double dt_;
  const TargetPlan& targets_;
  std::function<bool()> interrupt_;
  std::atomic<bool> stop_requested_{false};  // stop(), read by the run's per-step check
  int tile_w_, tile_h_;
  std::size_t capacity_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<TileSnapshot> queue_;
  bool done_ = false, stop_ = false;
  std::exception_ptr error_;
  RunSummary summary_;
  std::thread thread_;
};

}  // namespace clothsim::cli
