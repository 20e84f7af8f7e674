#include "reference_stand.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "clip/reference/lane_times.h"
#include "core/model/diagnostics.h"

namespace clothsim::clip {

ReferenceStand::ReferenceStand(const Model& model, Run& run, const std::vector<double>& lane_steps, double last_t)
    : model_(model), run_(run) {
  for (double h : lane_steps) {
    const auto at = std::find(steps_.begin(), steps_.end(), h);
    lane_step_.push_back(static_cast<std::size_t>(at - steps_.begin()));
    if (at == steps_.end()) steps_.push_back(h);
    slack_ = std::max(slack_, 1e-6 * h);
  }
  landed_.assign(steps_.size(), 0);
  last_slot_.resize(steps_.size());
  live_.assign(lane_steps.size(), true);
  live_lanes_.assign(steps_.size(), 0);
  for (std::size_t j : lane_step_) ++live_lanes_[j];
  for (double h : steps_)  // (formed as add() forms a request's time: none is past it by a rounding)
    last_needed_.push_back(h > 0.0 ? static_cast<double>(landing_step(last_t, h, 0)) * h : last_t);
  last_t_ = last_t;
  update_horizon();
}

void ReferenceStand::update_horizon() {
  horizon_ = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < steps_.size(); ++j)
    if (live_lanes_[j] > 0) horizon_ = std::max(horizon_, last_needed_[j]);
  if (energy_every_ > 0.0) horizon_ = std::max(horizon_, own_last_needed_);  // the inset's, to the end
}

void ReferenceStand::sample_energy(double every) {
  energy_every_ = every;
  const double H = run_.dt();
  own_last_needed_ = static_cast<double>(landing_step(last_t_, H, 0)) * H;
  slack_ = std::max(slack_, 1e-6 * H);
  update_horizon();
}

// The sample at t: where the run stands once advanced to t from its last sample (Run::advance_to).
std::shared_ptr<ReferenceStand::EnergySlot> ReferenceStand::ask_energy(double t) {
  const double H = run_.dt();
  const std::int64_t k = landing_step(t, H, own_landed_);
  if (last_energy_ && k == own_landed_) return last_energy_;  // the run would not have stepped
  own_landed_ = k;
  last_energy_ = std::make_shared<EnergySlot>();
  requests_.insert(Request{static_cast<double>(k) * H, asked_++, steps_.size(), nullptr, last_energy_, k});
  return last_energy_;
}

double ReferenceStand::next_energy_time() const {
  if (!(energy_every_ > 0.0)) return std::numeric_limits<double>::infinity();
  const double ts = static_cast<double>(sample_) * energy_every_;
  // (the sample where the run stands already is shared, not asked: the one after it counts)
  if (last_energy_ && landing_step(ts, run_.dt(), own_landed_) == own_landed_)
    return static_cast<double>(sample_ + 1) * energy_every_;
  return ts;
}

void ReferenceStand::add(const Target& target) {
  for (std::size_t j = 0; j < steps_.size(); ++j) {
    // Step 0: lanes that land on every target exactly (an adaptive pair's), a request per target.
    const bool exact = steps_[j] == 0.0;
    const std::int64_t k = exact ? landed_[j] + 1 : landing_step(target.t, steps_[j], landed_[j]);
    if (live_lanes_[j] == 0) {
      last_slot_[j] = nullptr;  // every lane of this step was dropped: nothing to serve
    } else if (!last_slot_[j] || k != landed_[j]) {  // a step whose runs did not step shares its last slot
      last_slot_[j] = std::make_shared<Slot>();
      requests_.insert(Request{exact ? target.t : static_cast<double>(k) * steps_[j], asked_++, j, last_slot_[j],
                               nullptr, -1});
    }
    landed_[j] = k;
  }
  std::vector<std::shared_ptr<Slot>> slots;
  for (std::size_t j : lane_step_) slots.push_back(last_slot_[j]);
  pending_.emplace_back(target, std::move(slots));
  if (!(energy_every_ > 0.0)) return;
  std::vector<std::shared_ptr<EnergySlot>> samples;  // as LaneWorker::run_targets samples a lane
  for (double ts : energy_samples_before(target.t, energy_every_, sample_)) samples.push_back(ask_energy(ts));
  samples.push_back(ask_energy(target.t));
  pending_energy_.push_back(std::move(samples));
}

bool ReferenceStand::front_ready() const {
  if (pending_.empty()) return false;
  const auto& slots = pending_.front().second;
  for (std::size_t lane = 0; lane < slots.size(); ++lane)
    if (live_[lane] && !slots[lane]->x) return false;
  if (!pending_energy_.empty())
    for (const auto& sample : pending_energy_.front())
      if (!sample->served) return false;
  return true;
}

Target ReferenceStand::pop(std::vector<Positions>& positions, std::vector<std::pair<double, double>>* energy) {
  if (energy) energy->clear();
  if (!pending_energy_.empty()) {
    for (const auto& sample : pending_energy_.front())
      if (sample->served && energy) energy->emplace_back(sample->t, sample->e);
    pending_energy_.pop_front();
  }
  positions.clear();
  for (const auto& slot : pending_.front().second) positions.push_back(slot ? slot->x : nullptr);
  const Target target = pending_.front().first;
  pending_.pop_front();
  return target;
}

double ReferenceStand::next_time() const {
  return requests_.empty() ? std::numeric_limits<double>::infinity() : requests_.begin()->t;
}

void ReferenceStand::drop_lane(std::size_t lane) {
  if (!live_[lane]) return;
  live_[lane] = false;
  const std::size_t j = lane_step_[lane];
  if (--live_lanes_[j] > 0) return;  // another lane of its step still needs its times
  for (auto r = requests_.begin(); r != requests_.end();) r = r->step == j ? requests_.erase(r) : std::next(r);
  update_horizon();
}

std::size_t ReferenceStand::positions_held() const {
  std::set<const std::vector<double>*> held;
  for (const auto& waiting : pending_)
    for (const auto& slot : waiting.second)
      if (slot && slot->x) held.insert(slot->x.get());
  return held.size();
}

long ReferenceStand::waiting_bound(const std::vector<double>& lane_steps, const TargetPlan& plan) {
  double largest = 0.0;
  for (double h : lane_steps) largest = std::max(largest, h);
  // A target is added only while its time is within the slack of the earliest time still
  // needed, and the oldest waiting target needs none later than its own plus the largest step
  // (its landing): the targets waiting lie within that step and twice the slack of the oldest.
  const double frames = std::floor(largest * (1.0 + 2e-6) * plan.fps()) + 2.0;  // (rounding allowed)
  const double off_frames = static_cast<double>(plan.size() - plan.frames());
  return static_cast<long>(std::min(static_cast<double>(plan.size()), frames + off_frames));
}

const ReferenceStand::Sample* ReferenceStand::reach_exactly(double t, std::int64_t k) {
  if (!last_.x.empty() && last_.t == t && last_.step == k) return &last_;  // (not the empty one before any)
  if (!exact_->advance_to(t) || exact_->stopped()) return nullptr;
  keep_sample(exact_->state());
  last_.step = k;  // (the grid's step, for the energy samples that share it)
  return &last_;
}

const ReferenceStand::Sample* ReferenceStand::reach(std::int64_t k) {
  if (exact_) return reach_exactly(static_cast<double>(k) * run_.dt(), k);
  for (const Sample* s : {&last_, &before_})
    if (s->step == k) return s;
  if (run_.diverged() && k >= run_.divergence()->step) return nullptr;
  if (k < run_.state().step)  // served in time order (LaneWorker::serve_reference): never a step passed
    throw std::logic_error("the reference lane was asked for step " + std::to_string(k) + ", having passed it (at " +
                           std::to_string(run_.state().step) + ")");
  if (!run_.advance_to(static_cast<double>(k) * run_.dt()) || run_.stopped()) return nullptr;
  keep_sample(run_.state());
  return &last_;
}

void ReferenceStand::keep_sample(const State& state) {
  const std::size_t n = 3 * static_cast<std::size_t>(model_.num_particles);
  std::swap(before_, last_);
  last_.step = state.step;
  last_.t = state.t;
  if (energy_every_ > 0.0) last_.energy = compute_energies(model_, state).total();
  last_.x.assign(state.x.data(), state.x.data() + n);
  last_.v.assign(state.v.data(), state.v.data() + n);
  if (check_ && !exact_ && state.step % 2 == 0) compare_with_check(state);
}

void ReferenceStand::compare_with_check(const State& state) {
  if (check_->diverged() || check_->stopped()) return;  // (the estimate was given up)
  if (state.step / 2 < check_->state().step) return;   // (a step the check has passed: none in time order)
  if (!check_->advance_to(state.t) || check_->stopped()) {
    estimated_error_ = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double d = analysis::largest_particle_distance(model_, check_->state(), state);
  estimated_error_ = std::isnan(estimated_error_) ? d : std::max(estimated_error_, d);
}

bool ReferenceStand::serve_next() {
  const Request request = *requests_.begin();  // (a copy: drop_lane may erase it on the way)
  const double H = run_.dt(), t = request.t;
  if (request.energy) {  // at one of the run's own steps
    const Sample* at = reach(request.k);
    if (!at) return false;
    request.energy->t = at->t;
    request.energy->e = at->energy;
    request.energy->served = true;
  } else if (exact_) {  // the adaptive solve's dense output, at t itself
    const Sample* at = reach_exactly(t, -1);
    if (!at) return false;
    request.slot->x = std::make_shared<const std::vector<double>>(at->x);
  } else if (const std::int64_t k = step_at(t, H); k >= 0) {  // one of the reference's own steps
    const Sample* at = reach(k);
    if (!at) return false;
    request.slot->x = std::make_shared<const std::vector<double>>(at->x);
  } else {
    const std::int64_t before = static_cast<std::int64_t>(std::floor(t / H));
    if (!reach(before)) return false;
    const Sample* b = reach(before + 1);
    if (!b) return false;
    if (before_.step != before) throw std::logic_error("the reference lane lost the step before a lane's time");
    auto x = std::make_shared<std::vector<double>>();
    hermite_positions(before_.x, before_.v, static_cast<double>(before) * H, b->x, b->v,
                      static_cast<double>(before + 1) * H, t, *x);
    request.slot->x = std::move(x);
  }
  requests_.erase(request);
  return true;
}

double reference_positions_bytes(const SceneDef& scene, const std::vector<double>& lane_steps,
                                 const TargetPlan& plan, std::size_t queue) {
  std::vector<double> distinct;
  for (double h : lane_steps)
    if (std::find(distinct.begin(), distinct.end(), h) == distinct.end()) distinct.push_back(h);
  const double copies = static_cast<double>(ReferenceStand::waiting_bound(lane_steps, plan)) +
                        static_cast<double>(queue) + 2.0;
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  return 24.0 * particles * (4.0 + copies * static_cast<double>(distinct.size()));
}

}  // namespace clothsim::clip
