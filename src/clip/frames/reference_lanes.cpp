#include "reference_lanes.h"

#include <chrono>

#include "clip/common/cli_common.h"

namespace clothsim::clip {

namespace {

// Adds the time a wait took to `total` (the pipeline's wait_seconds).
class WaitClock {
 public:
  explicit WaitClock(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~WaitClock() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

void ReferenceLanes::start(const Model& model, const TargetPlan& plan, const std::vector<Lane>& lanes,
                           const std::vector<const Model*>& lane_models, const PipelineConfig& config,
                           const std::function<bool()>& interrupt) {
  // One run of the reference for the error and the energy inset when they name the same.
  samples_energy_ = config.color == FieldKind::Error && config.reference && config.inset_energy &&
                    config.variant_references.empty() && config.energy_reference &&
                    same_run(*config.energy_reference, *config.reference);
  start_error(model, plan, lanes, lane_models, config, interrupt);
  if (config.inset_energy && config.energy_reference && !samples_energy_) {
    LaneNeeds n;  // the total energy at the inset's sample times, nothing else
    n.energy_every = 1.0 / plan.fps();
    energy_run_ = std::make_unique<LaneWorker>(model, *config.energy_reference, plan, n, kLaneQueueCapacity, interrupt);
  }
  energy_sampled_ = samples_energy_ || energy_run_;
}

// Lanes land on the first step at or past each frame time, not on it, each at its own step:
// the reference hands over its positions at every lane's landing time (its own step's state
// where it lands there, as the default's quarter step does, else interpolated between two),
// so no lane's error holds a time offset times |v|.
void ReferenceLanes::start_error(const Model& model, const TargetPlan& plan, const std::vector<Lane>& lanes,
                                 const std::vector<const Model*>& lane_models, const PipelineConfig& config,
                                 const std::function<bool()>& interrupt) {
  of_.assign(lanes.size(), -1);
  if (config.color != FieldKind::Error) return;
  std::vector<double> steps;
  for (const Lane& lane : lanes) steps.push_back(lane.landing_grid());
  const std::size_t queue = reference_queue_capacity(model.num_particles, steps);
  for (const VariantReference& v : config.variant_references) {
    LaneNeeds n;  // the positions at its value's lanes' times, nothing else
    n.stand_for = steps;
    n.adaptive_tolerance = v.tolerance;
    n.cache = config.reference_cache;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      n.serves.push_back(lane_models[i] == v.model);
      if (n.serves.back()) of_[i] = static_cast<int>(references_.size());
    }
    const std::size_t own_queue = reference_queue_capacity(v.model->num_particles, steps);  // its value's sheet
    references_.push_back({std::make_shared<LaneWorker>(*v.model, v.spec, plan, n, own_queue, interrupt), v.label, {}});
  }
  if (!config.variant_references.empty() || !config.reference) return;
  of_.assign(lanes.size(), 0);
  const double energy_every = samples_energy_ ? 1.0 / plan.fps() : 0.0;
  LaneNeeds n;  // the positions at the lanes' times (and the inset's energy), nothing else
  n.stand_for = std::move(steps);
  n.energy_every = energy_every;
  n.adaptive_tolerance = config.reference_tolerance;
  n.cache = config.reference_cache;
  references_.push_back({std::make_shared<LaneWorker>(model, *config.reference, plan, n, queue, interrupt), "", {}});
}

bool ReferenceLanes::collect(double& wait_seconds) {
  for (Reference& r : references_) {
    r.fresh = false;
    if (r.frozen) continue;
    LaneFrame f;
    WaitClock clock(wait_seconds);
    const bool got = r.worker->next(f);
    if (interrupted()) return false;
    if (got) {
      for (const auto& [time, e] : f.energy) energy_.add(time, e);  // (samples_energy_)
      r.frozen = f.frozen;
      r.fresh = !f.frozen;  // a diverged reference measures nothing
      r.frame = std::make_shared<const LaneFrame>(std::move(f));
    }
  }
  return collect_energy(wait_seconds);
}

// The inset's own reference run: its samples up to this target; false on a signal.
bool ReferenceLanes::collect_energy(double& wait_seconds) {
  if (!energy_run_ || energy_done_) return true;
  LaneFrame f;
  WaitClock clock(wait_seconds);
  const bool got = energy_run_->next(f);
  if (interrupted()) return false;
  for (const auto& [time, e] : f.energy) energy_.add(time, e);
  energy_done_ = !got || f.frozen;  // a diverged reference: the curves stop there
  return true;
}

void ReferenceLanes::drop_lane(std::size_t lane) {
  if (reference_of(lane) >= 0) references_[of_[lane]].worker->drop_lane(lane);
}

void ReferenceLanes::stop() {
  for (Reference& r : references_) r.worker->stop();
  if (energy_run_) energy_run_->stop();
}

const LaneFrame* ReferenceLanes::frame_for(std::size_t lane) const {
  return reference_of(lane) < 0 ? nullptr : references_[of_[lane]].frame.get();
}

bool ReferenceLanes::fresh_for(std::size_t lane) const {
  return reference_of(lane) >= 0 && references_[of_[lane]].fresh;
}

const LaneFrame* ReferenceLanes::diverged() const {
  for (const Reference& r : references_)
    if (r.frame && r.frame->divergence) return r.frame.get();
  return nullptr;
}

std::vector<ReferenceReport> ReferenceLanes::finish() {
  std::vector<ReferenceReport> out;
  for (Reference& r : references_) {
    r.worker->stop();  // it may be ahead of the last target a run stopped at
    r.worker->join();
    out.push_back({r.worker->result(), r.label});
  }
  if (energy_run_) {
    energy_run_->stop();
    energy_run_->join();
  }
  return out;
}

}  // namespace clothsim::clip
