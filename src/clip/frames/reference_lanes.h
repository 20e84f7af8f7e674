// The runs a pipeline keeps beside its lanes and never shows: the error colouring's references
// and the energy inset's.
//
// The error's reference is one run every lane is measured against, or under compare --vary one
// per value (PipelineConfig::variant_references): a value is a scene of its own, so each
// reference runs on its value's model and serves only that value's lanes (LaneNeeds::serves).
// A reference hands over, at every target, its positions at each lane's own landing time
// (reference_stand.h). The inset's reference is the error's own run when the two name the same
// run (one run samples its energy too), else a run of its own that only samples energy.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "frame_decoration.h"
#include "frame_pipeline.h"
#include "lane_worker.h"

namespace clothsim::clip {

class ReferenceLanes {
 public:
  // Starts what `config` asks for (nothing without --color error or an energy inset's
  // reference). `lane_models`: per lane, the model it runs. `model` and `plan` outlive this.
  void start(const Model& model, const TargetPlan& plan, const std::vector<Lane>& lanes,
             const std::vector<const Model*>& lane_models, const PipelineConfig& config,
             const std::function<bool()>& interrupt);
  // Each live reference's frame at the next target, and the inset's energy samples up to it;
  // false on a signal. The time spent waiting is added to `wait_seconds`.
  bool collect(double& wait_seconds);
  // Lane `lane` diverged: its reference serves it no more (and stops once no live lane needs it).
  void drop_lane(std::size_t lane);
  void stop();
  // The latest frame of lane's error reference (null: none, or not yet), and whether it was
  // handed over at this target and measures (a reference that diverged measures nothing).
  const LaneFrame* frame_for(std::size_t lane) const;
  bool fresh_for(std::size_t lane) const;
  // The frame of a reference that diverged, null when none did.
  const LaneFrame* diverged() const;
  // The inset's reference energy so far; null without one (the inset then shows E - E(0)).
  const EnergyHistory* energy() const { return energy_sampled_ ? &energy_ : nullptr; }
  // Stops and joins the references; their results, and per lane the index of its reference in
  // them (-1: none).
  std::vector<ReferenceReport> finish();
  int reference_of(std::size_t lane) const { return of_.empty() ? -1 : of_[lane]; }

 private:
  struct Reference {
    std::shared_ptr<LaneWorker> worker;
    std::string label;                       // VariantReference::label
    std::shared_ptr<const LaneFrame> frame;  // its latest
    bool frozen = false;                     // diverged: it measures nothing from then on
    bool fresh = false;                      // handed over at this target
  };
  void start_error(const Model& model, const TargetPlan& plan, const std::vector<Lane>& lanes,
                   const std::vector<const Model*>& lane_models, const PipelineConfig& config,
                   const std::function<bool()>& interrupt);
  bool collect_energy(double& wait_seconds);

  std::vector<Reference> references_;
  std::vector<int> of_;  // per lane: its reference's index in references_ (-1: none)
  std::unique_ptr<LaneWorker> energy_run_;  // PipelineConfig::energy_reference's own run
  bool samples_energy_ = false;             // ... or the error's reference, the same run
  bool energy_sampled_ = false;             // either: energy_ is the inset's reference
  bool energy_done_ = false;
  EnergyHistory energy_;                    // its samples so far
};

}  // namespace clothsim::clip
