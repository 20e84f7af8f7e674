#include "compare_runner.h"

#include <cinttypes>
#include <chrono>
#include <cstdio>

#include "snapshot.h"

namespace clothsim::cli {

RunWorker::RunWorker(const Model& model, IntegratorKind kind, double dt, const TargetPlan& targets,
                     int tile_width, int tile_height, std::size_t queue_capacity,
                     std::function<bool()> interrupt)
    : model_(model), kind_(kind), dt_(dt), targets_(targets), interrupt_(std::move(interrupt)),
      tile_w_(tile_width), tile_h_(tile_height), capacity_(std::max<std::size_t>(1, queue_capacity)) {
  summary_.kind = kind;
  summary_.dt = dt;
  thread_ = std::thread([this] { work(); });
}

RunWorker::~RunWorker() {
  stop();
  join();
}

void RunWorker::stop() {
  stop_requested_ = true;
  std::lock_guard<std::mutex> lock(mutex_);
  stop_ = true;
  changed_.notify_all();
}

void RunWorker::join() {
  if (thread_.joinable()) thread_.join();
}

RunSummary RunWorker::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return summary_;
}

bool RunWorker::next(TileSnapshot& out) {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!changed_.wait_for(lock, std::chrono::milliseconds(20), [this] { return !queue_.empty() || done_; }))
    if (interrupt_ && interrupt_()) return false;
  if (queue_.empty()) {
    if (error_) std::rethrow_exception(error_);
    return false;
  }
  out = std::move(queue_.front());
  queue_.pop_front();
  changed_.notify_all();
  return true;
}

void RunWorker::push(TileSnapshot snapshot) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < capacity_ || stop_; });
  if (stop_) return;
  queue_.push_back(std::move(snapshot));
  changed_.notify_all();
}

// The standard overlay plus what the run has cost so far: force evaluations (the
// machine-independent measure) and CPU ms per simulated second (what a user waits).
RenderFrame RunWorker::snapshot_of(const Run& run) const {
  const double cpu_seconds = run.totals().cpu_seconds;
  const double t = run.state().t;
  SnapshotText text{overlay_lines(model_, kind_, dt_, t), {}};
  char cost[96];
  if (t > 0.0)
    std::snprintf(cost, sizeof cost, "%" PRId64 " force evals  %.0f ms cpu/sim s",
                  run.totals().force_evals, 1e3 * cpu_seconds / t);
  else
    std::snprintf(cost, sizeof cost, "%" PRId64 " force evals", run.totals().force_evals);
  text.lines.push_back(cost);
  // An implicit step that missed its tolerance is a result, shown on the tile and its sheet
  // cell as a banner (a later divergence replaces it).
  if (run.totals().unconverged_steps > 0) {
    char banner[64];
    std::snprintf(banner, sizeof banner, "NOT CONVERGED (%" PRId64 " steps)",
                  run.totals().unconverged_steps);
    text.banner = banner;
  }
  RenderFrame frame = make_render_frame(model_, run.state(), text);
  frame.width = tile_w_;
  frame.height = tile_h_;
  return frame;
}

void RunWorker::work() {
  try {
    Run run(model_, kind_, dt_);
    run.set_stop_check([this] { return stop_requested_.load(std::memory_order_relaxed) || (interrupt_ && interrupt_()); });
    // The initial state is the last good frame until a target is reached, so a run that
    // diverges before the first target still has a picture to freeze on.
    RenderFrame last_good = snapshot_of(run);
    double last_good_t = 0.0;
    TargetPlan::Cursor cursor(targets_);
    for (Target target; cursor.next(target);) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stop_) break;
      }
      const bool ok = run.advance_to(target.t);
      if (run.stopped()) break;
      if (!ok) {
        const Divergence& d = *run.divergence();
        TileSnapshot frozen{std::move(last_good), true};
        mark_diverged(frozen.frame, d);
        push(std::move(frozen));
        break;
      }
      last_good = snapshot_of(run);
      last_good_t = run.state().t;
      push(TileSnapshot{last_good, false});
    }
    std::lock_guard<std::mutex> lock(mutex_);
    summary_.t = last_good_t;
    summary_.totals = run.totals();
    summary_.divergence = run.divergence();
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  done_ = true;
  changed_.notify_all();
}

}  // namespace clothsim::cli
