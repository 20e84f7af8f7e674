#include "lane_worker.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "clip/frames/reference_record.h"
#include "clip/reference/reference_stand.h"
#include "clip/reference/lane_times.h"
#include "core/model/diagnostics.h"
#include "study/reference.h"
#include "view/snapshot.h"

namespace clothsim::clip {

LaneWorker::LaneWorker(const Model& model, const MethodSettings& settings, Lane spec, const TargetPlan& targets,
                       LaneNeeds needs, std::size_t queue_capacity, std::function<bool()> interrupt)
    : model_(model), settings_(settings), spec_(std::move(spec)), targets_(targets), needs_(needs),
      interrupt_(std::move(interrupt)),
      reference_(!needs_.stand_for.empty()),
      capacity_(std::max<std::size_t>(1, queue_capacity)) {
  if (!needs_.stand_for.empty()) set_lane_steps(needs_.stand_for);
  for (std::size_t i = 0; i < needs_.serves.size(); ++i)
    if (!needs_.serves[i]) drop_lane(i);  // before the thread: its first target asks nothing of them
  result_.spec = spec_;
  thread_ = std::thread([this] { work(); });
}

LaneWorker::~LaneWorker() {
  stop();
  join();
}  // (here, where ReferenceRecorder is complete)

void LaneWorker::stop() {
  stop_requested_ = true;
  std::lock_guard<std::mutex> lock(mutex_);
  stop_ = true;
  changed_.notify_all();
}

std::size_t reference_queue_capacity(int particles, const std::vector<double>& lane_steps) {
  std::vector<double> distinct;
  for (double h : lane_steps)
    if (std::find(distinct.begin(), distinct.end(), h) == distinct.end()) distinct.push_back(h);
  const double frame = 24.0 * std::max(1, particles) * static_cast<double>(std::max<std::size_t>(1, distinct.size()));
  return std::clamp<std::size_t>(static_cast<std::size_t>(kReferenceAheadBytes / frame), kLaneQueueCapacity, 32);
}

bool same_run(const Lane& started, const Lane& wanted) {
  return started.same_as(wanted) && started.step_text == wanted.step_text;
}

void LaneWorker::set_lane_steps(std::vector<double> lane_steps) {
  dropped_ = std::make_unique<std::atomic<bool>[]>(lane_steps.size());
  for (std::size_t i = 0; i < lane_steps.size(); ++i) dropped_[i] = false;
  lane_steps_ = std::move(lane_steps);
}

void LaneWorker::drop_lane(std::size_t lane) {
  if (lane >= lane_steps_.size() || dropped_[lane].exchange(true)) return;
  ++drops_;
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
  if (recorder_) recorder_->add(frame);  // (the reference's thread, the recorder's only user)
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return queue_.size() < capacity_ || stop_; });
  if (stop_) return;
  queue_.push_back(std::move(frame));
  changed_.notify_all();
}

// What the outputs need of `state` (the run's current one, or its last finite state).
LaneFrame LaneWorker::frame_of(const Run& run, const State& state) const {
  LaneFrame f;
  f.t = f.shown_t = state.t;
  f.step = state.step;
  f.totals = run.totals();
  if (needs_.picture) f.frame = make_render_frame(model_, state, needs_.look);
  if (needs_.positions) {
    const Eigen::Index n = 3 * static_cast<Eigen::Index>(model_.num_particles);
    f.x.assign(state.x.data(), state.x.data() + n);  // particles come first, column-major
  }
  if (needs_.field == FieldKind::Strain) f.field = vertex_strain(model_, state);
  if (needs_.field == FieldKind::Speed) f.field = vertex_speed(model_, state);
  if (needs_.bodies) {
    f.bodies.x = state.x;
    f.bodies.v = state.v;
    f.bodies.t = state.t;
    f.bodies.step = state.step;
  }
  return f;
}

namespace {
// What the reference runs: the run, or the adaptive solve in its place (LaneNeeds::adaptive_tolerance).
struct ReferenceSource {
  Run& run;
  analysis::AdaptiveReference* exact;
  RunTotals totals() const { return exact ? exact->totals() : run.totals(); }
  std::int64_t step() const { return exact ? exact->state().step : run.state().step; }
  double t() const { return exact ? exact->time() : run.state().t; }
  bool stopped() const { return exact ? exact->stopped() : run.stopped(); }
  std::optional<Divergence> divergence() const { return exact ? exact->divergence() : run.divergence(); }
  void set_stop_check(const std::function<bool()>& stop) const {
    run.set_stop_check(stop);
    if (exact) exact->set_stop_check(stop);
  }
};

// The reference's last frame once it diverged: where and when, and what it cost.
LaneFrame frozen_reference(const ReferenceSource& source) {
  LaneFrame frozen;
  frozen.divergence = source.divergence();
  frozen.t = frozen.divergence->t;
  frozen.step = source.step();
  frozen.totals = source.totals();
  frozen.frozen = true;
  return frozen;
}
}  // namespace

// The reference lane's loop (LaneNeeds::stand_for): targets are added as the times they need
// come due, the earliest needed time is served next, and a target's frame is handed over once
// every lane's positions for it are known (reference_stand.h).
// True when it ran to its end (every target served, its horizon passed, or diverged), false
// when stopped or interrupted first.
bool LaneWorker::serve_reference(Run& run, analysis::AdaptiveReference* exact) {
  ReferenceStand stand(model_, run, lane_steps_, targets_.last_time());
  if (exact) stand.serve_exactly(*exact);
  std::optional<Run> check;  // the fixed-step reference's own error: a run at twice its step (reference_stand.h)
  if (!exact) stand.check_against(check.emplace(model_, spec_.kind, 2.0 * run.dt(), settings_));
  if (check) check->set_stop_check([this] { return stop_asked(); });
  const ReferenceSource source{run, exact};
  if (needs_.energy_every > 0.0) stand.sample_energy(needs_.energy_every);  // the inset's reference too
  int applied = 0;  // drops_ passed on to the stand
  const auto apply_drops = [&] {
    if (drops_.load(std::memory_order_acquire) == applied) return;
    applied = 0;
    for (std::size_t i = 0; i < lane_steps_.size(); ++i)
      if (dropped_[i].load(std::memory_order_acquire)) {
        stand.drop_lane(i);
        ++applied;
      }
  };
  // Between any two steps: stopped, or no live lane can need a time from here on (every time
  // a live lane needs is at or before the horizon, and the run only goes forward).
  source.set_stop_check([&] {
    if (stop_asked()) return true;
    apply_drops();
    return source.t() >= stand.horizon();
  });
  TargetPlan::Cursor cursor(targets_);
  Target next;
  bool more = cursor.next(next);
  const auto hand_over = [&] {  // the oldest target, with what is known of it
    LaneFrame f;
    f.t = stand.pop(f.x_for, &f.energy).t;
    f.step = source.step();
    f.totals = source.totals();
    f.reference_error = exact ? exact->estimated_error() : stand.estimated_error();
    push(std::move(f));
  };
  bool complete = false;
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) break;
    }
    apply_drops();
    if (stand.front_ready()) {
      hand_over();
      if (!more && stand.empty()) {  // the last target (the pipeline may stop it from here on)
        complete = true;
        break;
      }
      continue;
    }
    if (more && stand.add_before_serving(next.t)) {
      stand.add(next);
      more = cursor.next(next);
      continue;
    }
    if (stand.empty()) {  // every target served
      complete = true;
      break;
    }
    if (!stand.serve_next()) {
      if (source.stopped() && stop_asked()) break;
      complete = true;
      if (source.stopped()) {
        // Past the horizon: what every live lane needs was served (the targets still to add
        // would need later times), so the targets waiting go out, the dropped lanes' positions
        // missing, and the rest with none.
        while (!stand.empty()) hand_over();
        for (; more; more = cursor.next(next)) {
          stand.add(next);
          hand_over();
        }
        break;
      }
      // The targets waiting go out with what was served of them (a lane of a small step was
      // measured up to the blow-up even if one of a large step, needing a later time, was not).
      while (!stand.empty()) hand_over();
      push(frozen_reference(source));  // a diverged reference measures nothing from here on
      break;
    }
  }
  finish_reference(run, exact, check ? &*check : nullptr, stand.estimated_error());
  return complete;
}

void LaneWorker::finish_reference(const Run& run, const analysis::AdaptiveReference* exact, const Run* check,
                                  double estimated_error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (exact) {  // it ran in place of the run
    result_.t = exact->state().t;
    result_.totals = exact->totals();
    result_.divergence = exact->divergence();
    result_.adaptive_tolerance = exact->tolerance();
    result_.check_tolerance = exact->check_tolerance();
    result_.estimated_error = exact->estimated_error();
    return;
  }
  result_.t = run.state().t;  // as far as it ran (past the last target where a lane stands past it)
  result_.totals = run.totals();
  result_.divergence = run.divergence();
  if (check) {  // its work is the reference's too
    result_.totals.cpu_seconds += check->totals().cpu_seconds;
    result_.totals.force_evals += check->totals().force_evals;
    result_.check_dt = check->dt();
    result_.estimated_error = estimated_error;
  }
}

// A lane's loop: each target in turn, stepped to and handed over (a frozen frame and the end
// on divergence).
void LaneWorker::run_targets(Run& run) {
  TargetPlan::Cursor cursor(targets_);
  double reached = 0.0;
  long sample = 0;  // the next energy sample, at sample * energy_every
  std::vector<std::pair<double, double>> energy;
  const auto record_energy = [&] { energy.emplace_back(run.state().t, compute_energies(model_, run.state()).total()); };
  // LaneNeeds::hold_sane: what a picture reads of the last state handed over (the start first).
  State sane;
  const auto keep_sane = [&] {
    if (!needs_.hold_sane) return;
    const State& s = run.state();
    sane.x = s.x, sane.v = s.v, sane.inv_mass = s.inv_mass, sane.t = s.t, sane.step = s.step;
  };
  keep_sane();
  for (Target target; cursor.next(target);) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) break;
    }
    // Samples between targets: advancing to them takes the same steps (a Run steps until
    // t >= target), so the energy curve costs a pass over the bodies per sample, no more.
    bool ok = true;
    if (needs_.energy_every > 0.0) {
      for (double ts : energy_samples_before(target.t, needs_.energy_every, sample)) {
        ok = run.advance_to(ts);
        if (!ok || run.stopped()) break;
        record_energy();
      }
      if (run.stopped()) break;
    }
    if (ok) ok = run.advance_to(target.t);
    if (run.stopped()) break;
    if (!ok) {
      // The picture (and field) of the last finite state at the step divergence names, or of
      // the last sane one; the metrics of the state the run stopped in, which is what
      // `run --metrics` records.
      const Divergence& d = *run.divergence();
      const bool drawn = needs_.picture || needs_.field != FieldKind::None || needs_.bodies;
      LaneFrame frozen = frame_of(run, needs_.hold_sane ? sane : drawn ? run.last_finite_state() : run.state());
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
    keep_sane();
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
}

// The reference from the cache when it holds it, else computed and stored there
// (reference_record.h).
void LaneWorker::cached_reference(Run& run) {
  const analysis::ReferenceCache cache(needs_.cache);
  const std::optional<std::string> key =
      cache.enabled() ? reference_cache_key(model_, spec_, needs_.adaptive_tolerance, lane_steps_, needs_.serves,
                                            needs_.energy_every, targets_)
                      : std::nullopt;
  if (key && replay_reference(cache, *key)) return;
  const double limit = std::min(kReferenceRecordLimit, static_cast<double>(needs_.cache.max_bytes));
  if (key) recorder_ = std::make_unique<ReferenceRecorder>(static_cast<std::size_t>(limit));
  bool complete = false;
  if (needs_.adaptive_tolerance > 0.0) {
    analysis::AdaptiveReference exact(model_, needs_.adaptive_tolerance);
    complete = serve_reference(run, &exact);
  } else {
    complete = serve_reference(run);
  }
  LaneResult result = this->result();
  if (!cache.enabled()) {
    result.cache = "off";
  } else if (!key) {
    result.cache = "not cached";
  } else if (complete && !recorder_->overflowed()) {
    std::string why;
    if (cache.store(*key, recorder_->finish(result), &why)) {
      result.cache = "stored";
      result.cache_file = cache.path_of(*key);
    } else {
      result.cache = "not stored: " + why;
    }
  } else {
    result.cache = complete ? "not stored: larger than " + std::to_string(static_cast<long>(limit / (1 << 20))) + " MB"
                            : "not stored: stopped before its end";
  }
  recorder_.reset();
  std::lock_guard<std::mutex> lock(mutex_);
  result_.cache = result.cache;
  result_.cache_file = result.cache_file;
}

// Serves the record stored under `key`, frame for frame; false (nothing handed over) when there
// is none, or it does not decode (then removed, as a damaged entry is).
bool LaneWorker::replay_reference(const analysis::ReferenceCache& cache, const std::string& key) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  const std::optional<std::string> payload = cache.load(key);
  if (!payload) return false;
  std::optional<ReferenceRecord> record = decode_reference_record(*payload);
  if (!record) {
    std::remove(cache.path_of(key).c_str());
    return false;
  }
  for (LaneFrame& f : record->frames) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) break;
    }
    push(std::move(f));
  }
  LaneResult r = std::move(record->result);
  r.spec = spec_;
  r.cache = "reused";
  r.cache_file = cache.path_of(key);
  r.computed_cpu_seconds = r.totals.cpu_seconds;
  r.totals.cpu_seconds = thread_cpu_seconds() - cpu_start;
  r.totals.sim_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::lock_guard<std::mutex> lock(mutex_);
  result_ = std::move(r);
  return true;
}

bool LaneWorker::stop_asked() const {
  return stop_requested_.load(std::memory_order_relaxed) || (interrupt_ && interrupt_());
}

void LaneWorker::work() {
  try {
    Run run(model_, spec_.kind, spec_.dt, settings_);
    run.set_stop_check([this] { return stop_asked(); });
    // CLOTHSIM_NEWTON_TRACE=1: implicit_euler's Newton trace on stderr (docs/implicit_euler.md, "The Newton trace").
    if (std::getenv("CLOTHSIM_NEWTON_TRACE")) run.set_newton_trace([](const char* line) { std::fputs(line, stderr); });
    if (!reference_) run_targets(run);
    else cached_reference(run);
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  done_ = true;
  changed_.notify_all();
}

}  // namespace clothsim::clip
