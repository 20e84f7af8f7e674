// Stability: the largest step each integrator survives on a scene, found by bisection in log
// dt (docs/integrators.md, "Stability", and "How the search decides" there for the why).
//
// "Survives": runs 0 to T without diverging under the study's tighter bounds (max_strain 2,
// energy_factor 100: an unstable run can settle into a bounded, wrong orbit that run's loose
// bounds let pass) and, for implicit_euler, with every Newton solve converged (a missed
// tolerance is Failure::NotConverged, not a stable run). A trial takes at least
// kMinTrialSteps steps, so the largest dt tried is at most T / kMinTrialSteps.
// The search assumes stability monotone in dt: max_dt first (stable there: "stable at the
// largest dt tried"); else from the first guess (2 / max(w_max, c_max)) double or halve to a
// bracket ("unstable at every dt tried" below min_dt); then bisect to 1 + precision. The
// answer is the bracket's stable end. Slowly growing instabilities (explicit Euler, midpoint
// at small h) pass a finite-time test: the result is "stable over T".
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "study.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "core/model/stiffness_estimate.h"

namespace clothsim::analysis {

constexpr int kMinTrialSteps = 20;

struct StabilitySpec {
  std::vector<IntegratorKind> integrators;
  double duration = 0.0;        // T, s: each trial runs from 0 to T
  double min_dt = 0.0;          // s, smallest step tried
  double max_dt = 0.0;          // s, largest step tried, <= duration / kMinTrialSteps
  double precision = 0.02;      // relative width of the final bracket
  double energy_factor = 100.0; // replaces Model::divergence.max_energy_factor in trials
  double max_strain = 2.0;      // replaces Model::divergence.max_strain in trials
  double first_guess = 0.0;     // s; 0: 2 / max(w_max, c_max) of the model, clamped to the range
  std::vector<double> frame_dts;  // s, steps implicit_euler is also run at over T (one step per
                                  // video frame, however few steps that is), reported apart
  int jobs = 0;                 // threads; <= 0: hardware_concurrency
};

enum class StabilityOutcome {
  Bracketed,      // stable_dt <= limit < unstable_dt, unstable_dt / stable_dt <= 1 + precision
  StableAtMax,    // stable at max_dt: the limit (if any) is above the range tried
  UnstableAtMin,  // unstable at min_dt: the limit (if any) is below the range tried
  Stopped,        // the caller stopped the search
};
const char* outcome_name(StabilityOutcome outcome);  // "bracketed", "stable_at_max", ...

// How a trial failed: the engine called it diverged, or (implicit_euler) it reached T but
// some of its steps' solves ended above their tolerance. Divergence wins when both.
enum class Failure { None, Diverged, NotConverged };
const char* failure_name(Failure failure);  // "", "diverged", "not_converged"

// One step per frame (StabilitySpec::frame_dts): implicit_euler run over T at that step.
struct FrameStepResult {
  double dt = 0.0;                  // s
  Failure failure = Failure::None;  // None: reached T with every step converged
  std::int64_t steps = 0;           // steps taken (to T, or to the divergence)
  std::int64_t unconverged_steps = 0;
  double diverged_at = 0.0;         // s, when failure == Diverged
  bool stopped = false;             // the caller stopped the run
  // > 0: the course's fixed point (implicit_euler with solver: fixed_point) at this many
  // iterations a step: no solve and no tolerance, so nothing converges or fails to.
  int fixed_point_iterations = 0;
};
// "1/60 s: ok, 12 steps converged", "1/30 s: 3 of 6 steps not converged",
// "1/30 s: diverged at t = 0.1 s"; the fixed point's "1/60 s: ok, 12 steps of 1 fixed-point
// iteration (no solve to converge)"; a step that is not 1/N s is written in seconds.
std::string frame_step_text(const FrameStepResult& r);

struct StabilityLimit {
  IntegratorKind integrator{};
  std::size_t lane = 0;        // index into spec.integrators
  double value = 0.0;          // the swept parameter's value (0 outside a sweep)
  StabilityOutcome outcome = StabilityOutcome::Stopped;
  double stable_dt = 0.0;      // s, largest dt that ran to T (NaN when none did)
  double unstable_dt = 0.0;    // s, smallest dt that diverged (NaN when none did)
  Failure failure = Failure::None;  // how the run at unstable_dt failed
  std::string reason;          // and in words: "at t = 0.1 s: <divergence reason>" or
                               // "2 of 40 steps not converged (largest final residual 0.01)"
  std::vector<FrameStepResult> frame_steps;  // implicit_euler: one per spec.frame_dts, in order
  int trials = 0;              // runs made
  double cpu_seconds = 0.0;    // summed over the trials
  StiffnessEstimate estimate;  // of the model searched
};

// Checks the spec; throws StudyError naming the problem.
void check(const StabilitySpec& spec);

// One search: `kind` on `model` under `settings` (a lane's; without them the model's own).
StabilityLimit largest_stable_dt(const Model& model, const MethodSettings& settings, IntegratorKind kind,
                                 const StabilitySpec& spec, const std::function<bool()>& stop = {});
StabilityLimit largest_stable_dt(const Model& model, IntegratorKind kind, const StabilitySpec& spec,
                                 const std::function<bool()>& stop = {});

// A swept parameter's value and the model it gives.
struct StabilityCase {
  StabilityCase() = default;
  StabilityCase(double v, const Model* m, std::vector<MethodSettings> lanes = {})
      : value(v), model(m), lane_settings(std::move(lanes)) {}
  double value = 0.0;
  const Model* model = nullptr;
  // Per integrators entry, the settings that lane searches with on this case's model: its own
  // solver settings (the fixed point, iteration counts). Empty: the model's own.
  std::vector<MethodSettings> lane_settings;
};
MethodSettings case_lane_settings(const StabilityCase& c, std::size_t lane);

// A search's rough cost in force-evaluation equivalents, for sharding only (shard.h): the
// search's own trials replayed on the limit predicted_limit gives with the dampers' bound
// c_max / 2.4 (a stable trial runs T / dt steps, an unstable one 0.3 of them), each step
// its evaluations (implicit_euler: 42 x (1 + 5.6e-5 P w_max dt), its frame-step runs added).
// Fitted on the drape (docs/cluster.md); no timing enters it, so every shard agrees.
// `settings`: the lane's (the fixed point's limit is not backward Euler's); without them the model's.
double search_cost(const Model& model, const MethodSettings& settings, IntegratorKind kind, const StabilitySpec& spec);
double search_cost(const Model& model, IntegratorKind kind, const StabilitySpec& spec);

// Every (case, integrator) search, spread over the cores; results case by case, integrators
// in spec order. Searches the caller stopped are left out.
std::vector<StabilityLimit> stability_sweep(const std::vector<StabilityCase>& cases,
                                            const StabilitySpec& spec, const StudyHooks& hooks = {});

// The searches `items` only (item = case index x integrators + integrator index, ascending),
// `finished` told of each as it completes (calls serialised): a shard's part (shard.h).
std::vector<StabilityLimit> stability_sweep_items(
    const std::vector<StabilityCase>& cases, const StabilitySpec& spec, const std::vector<std::size_t>& items,
    const StudyHooks& hooks = {}, const std::function<void(std::size_t, const StabilityLimit&)>& finished = {});

}  // namespace clothsim::analysis
