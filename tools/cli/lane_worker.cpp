#include "lane_worker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "diagnostics.h"
#include "lane_times.h"
#include "snapshot.h"

namespace clothsim::cli {

LaneWorker::LaneWorker(const Model& model, LaneSpec spec, const TargetPlan& targets, LaneNeeds needs,
                       std::size_t queue_capacity, std::function<bool()> interrupt)
    : model_(model), spec_(std::move(spec)), targets_(targets), needs_(needs), interrupt_(std::move(interrupt)),
      capacity_(std::max<std::size_t>(1, queue_capacity)) {
  result_.spec = spec_;
  thread_ = std::thread([this] { work(); });
}

LaneWorker::~LaneWorker() {
  stop();
  join();
}

void LaneWorker::stop() {
  stop_requested_ = true;
  std::lock_guard<std::mutex> lock(mutex_);
  stop_ = true;
  changed_.notify_all();
}

void LaneWorker::join() {
  if (thread_.joinable()) thread_.join();
}

LaneResult LaneWorker::result() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return result_;
}

bool LaneWorker::next(LaneFrame& out) {
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

void LaneWorker::push(LaneFrame frame) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < capacity_ || stop_; });
  if (stop_) return;
  queue_.push_back(std::move(frame));
  changed_.notify_all();
}

// What the outputs need of `state` (the run's current one, or its last finite state).
LaneFrame LaneWorker::frame_of(const Run& run, const State& state) const {
  LaneFrame f;
  f.t = state.t;
  f.step = state.step;
  f.totals = run.totals();
  if (needs_.picture) f.frame = make_render_frame(model_, state, {});
  if (needs_.positions) {
    const Eigen::Index n = 3 * static_cast<Eigen::Index>(model_.num_particles);
    f.x.assign(state.x.data(), state.x.data() + n);  // particles come first, column-major
  }
  if (needs_.field == FieldKind::Strain) f.field = vertex_strain(model_, state);
  if (needs_.field == FieldKind::Speed) f.field = vertex_speed(model_, state);
  return f;
}

// Advances the reference to the times where runs of the steps in stand_for land at `target`,
// in increasing order, and fills out.x_for with its positions at each: its state where one of
// its steps lands there, else the Hermite interpolant through the states of the two steps
// around it. False once the reference diverged (or the run was stopped).
bool LaneWorker::stand_in(Run& run, const Target& target, LaneFrame& out) {
  const std::size_t n = 3 * static_cast<std::size_t>(model_.num_particles);
  const double H = run.dt();
  // The reference at its step k (only forward; the last two kept: an interval serves the
  // lanes whose times fall in it).
  const auto reach = [&](std::int64_t k) -> const StandSample* {
    for (const StandSample* s : {&stand_last_, &stand_before_})
      if (s->step == k) return s;
    if (k < run.state().step)  // times only increase, and the step before the last is kept
      throw std::logic_error("the reference lane was asked for a step it has passed");
    if (!run.advance_to(static_cast<double>(k) * H) || run.stopped()) return nullptr;
    std::swap(stand_before_, stand_last_);
    stand_last_.step = run.state().step;
    stand_last_.x.assign(run.state().x.data(), run.state().x.data() + n);
    stand_last_.v.assign(run.state().v.data(), run.state().v.data() + n);
    return stand_last_.step == k ? &stand_last_ : nullptr;
  };
  out.x_for.assign(needs_.stand_for.size(), {});
  stand_landed_.resize(needs_.stand_for.size(), 0);
  std::vector<std::pair<double, std::size_t>> times;  // (landing time, lane)
  for (std::size_t j = 0; j < needs_.stand_for.size(); ++j) {
    const double h = needs_.stand_for[j];
    stand_landed_[j] = landing_step(target.t, h, stand_landed_[j]);
    times.emplace_back(static_cast<double>(stand_landed_[j]) * h, j);
  }
  std::sort(times.begin(), times.end());
  for (const auto& [t, j] : times) {
    if (const std::int64_t k = step_at(t, H); k >= 0) {  // one of the reference's steps
      const StandSample* at = reach(k);
      if (!at) return false;
      out.x_for[j] = at->x;
      continue;
    }
    const std::int64_t before = static_cast<std::int64_t>(std::floor(t / H));
    const StandSample* a = reach(before);
    if (!a) return false;
    const StandSample a_copy = *a;  // (reach may swap the two kept samples)
    const StandSample* b = reach(before + 1);
    if (!b) return false;
    hermite_positions(a_copy.x, a_copy.v, static_cast<double>(before) * H, b->x, b->v,
                      static_cast<double>(before + 1) * H, t, out.x_for[j]);
  }
  return true;
}

void LaneWorker::work() {
  try {
    Run run(model_, spec_.kind, spec_.dt);
    run.set_stop_check([this] { return stop_requested_.load(std::memory_order_relaxed) || (interrupt_ && interrupt_()); });
    TargetPlan::Cursor cursor(targets_);
    double reached = 0.0;
    long sample = 0;  // the next energy sample, at sample * energy_every
    std::vector<std::pair<double, double>> energy;
    const auto record_energy = [&] { energy.emplace_back(run.state().t, compute_energies(model_, run.state()).total()); };
    for (Target target; cursor.next(target);) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stop_) break;
      }
      // Samples between targets: advancing to them takes the same steps (a Run steps until
      // t >= target), so the energy curve costs a pass over the bodies per sample, no more.
      bool ok = true;
      if (needs_.energy_every > 0.0) {
        for (double ts = static_cast<double>(sample) * needs_.energy_every; ts < target.t - 1e-9 && ok;
             ts = static_cast<double>(++sample) * needs_.energy_every) {
          ok = run.advance_to(ts);
          if (run.stopped()) break;
          if (ok) record_energy();
        }
        if (run.stopped()) break;
      }
      LaneFrame stood;  // the reference's positions at the lanes' times
      if (ok) ok = needs_.stand_for.empty() ? run.advance_to(target.t) : stand_in(run, target, stood);
      if (run.stopped()) break;
      if (!ok) {
        // The picture (and field) of the last finite state at the step divergence names; the
        // metrics of the state the run stopped in, which is what `run --metrics` records.
        const Divergence& d = *run.divergence();
        LaneFrame frozen = frame_of(run, needs_.picture || needs_.field != FieldKind::None
                                             ? run.last_finite_state() : run.state());
        if (needs_.metrics) frozen.metrics = run.metrics();
        frozen.t = d.t;
        frozen.energy = std::move(energy);
        frozen.divergence = d;
        frozen.frozen = true;
        frozen.x.clear();  // no reference exists at the divergence's instant: no error field
        reached = d.t;
        push(std::move(frozen));
        break;
      }
      LaneFrame f = frame_of(run, run.state());
      f.x_for = std::move(stood.x_for);
      if (needs_.metrics) f.metrics = run.metrics();
      if (needs_.energy_every > 0.0) {
        record_energy();
        f.energy = std::move(energy);
        energy.clear();
      }
      reached = run.state().t;
      push(std::move(f));
    }
    std::lock_guard<std::mutex> lock(mutex_);
    result_.t = reached;
    result_.totals = run.totals();
    result_.divergence = run.divergence();
    if (needs_.final_state && !run.diverged()) result_.final_state = run.state();
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  done_ = true;
  changed_.notify_all();
}

}  // namespace clothsim::cli
