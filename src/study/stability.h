// Stability: the largest step each integrator survives on a scene, found by bisection.
//
// "Survives" means: runs from t = 0 to T without the engine calling it diverged (a
// non-finite value, a spring stretched past max_strain, or kinetic energy past
// energy_factor x the scene's energy scale; see diagnostics.h and Model::energy_scale)
// and, for implicit_euler, with every step's solve converged. A run whose Newton solve
// missed its tolerance has not computed backward Euler's step, so that it stayed bounded
// says nothing about the method: it fails, and `failure` says it failed so
// (Failure::NotConverged) rather than by diverging. For implicit Euler, which backward
// Euler's theory calls stable at every step, the study's limit is thus where its solve
// stops converging, which is what bounds its usable step in practice.
// The study tightens both of the engine's bounds, because an unstable run need not stay
// unstable-looking: once its amplitude passes a spring's rest length the spring collapses
// through its anchor, the force stops growing with the stretch, and the run settles into a
// bounded, wrong orbit that the engine's loose bounds (strain 10, energy 1e4 x scale) let
// pass (RK4 on spring.yaml with k = 25 N/m "survived" w h = 3.08 that way, beyond its
// 2.83). So by default:
// - max_strain 2: no cloth is stretched to three times its rest length, and the bounded
//   wrong orbits do stretch their springs that far (the engine samples strain every 64 steps);
// - energy_factor 100: the energy scale already bounds what a passive scene can hold (its
//   potential energy released over its own size, plus its initial energy), so 100 times
//   it is no state a stable method reaches.
// Symplectic Euler's energy swings by 1 / (1 - (w h / 2)^2) below its limit; the bounds
// allow that up to within 1 % of w h = 2.
//
// Slow growth. An unstable method whose amplification is barely above 1 takes long to
// reach any bound: undamped, explicit Euler's energy grows like exp(w^2 h t) and
// midpoint's like exp(w^4 h^3 t / 4), so at small h they pass a finite-time test. The
// result is therefore "stable over T", and T and the smallest dt tried must be chosen so
// that the growth one wants to see, exp(rate x T), exceeds the bound: the tests on the
// undamped spring use T = 400 s and steps down to w h = 0.2, where midpoint's energy grows
// by e^8. Symplectic Euler and RK4 have no slow side: beyond w h = 2 and 2.83 their
// amplification jumps well above 1 (the limits are sharp), and below, their energy stays
// within a bounded band.
//
// A trial must take at least kMinTrialSteps steps: two steps of explicit Euler at 1000 x
// its limit need not blow up yet, and would make "stable at the largest dt tried" a lie.
// So the largest step tried is at most T / kMinTrialSteps (check() says so otherwise).
//
// The search, in log dt, assuming (as linear theory says) that stability is monotone in dt:
// 1. the largest dt tried, max_dt: stable there -> "stable at the largest dt tried" (no
//    larger number is invented);
// 2. from a first guess (2 / max(w_max, c_max) from stiffness_estimate.h), double while
//    stable or halve while unstable until a stable/unstable pair brackets the limit; no
//    stable dt down to min_dt -> "unstable at every dt tried";
// 3. bisect the bracket at its geometric mean until unstable / stable <= 1 + precision.
// The answer is the largest dt that ran (the bracket's stable end).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "study.h"
#include "core/integrators/integrator_kind.h"
#include "core/model.h"
#include "core/stiffness_estimate.h"

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
};
// "1/60 s: ok, 12 steps converged", "1/30 s: 3 of 6 steps not converged",
// "1/30 s: diverged at t = 0.1 s"; a step that is not 1/N s is written in seconds.
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

// One search: `kind` on `model`.
StabilityLimit largest_stable_dt(const Model& model, IntegratorKind kind, const StabilitySpec& spec,
                                 const std::function<bool()>& stop = {});

// A swept parameter's value and the model it gives.
struct StabilityCase {
  StabilityCase() = default;
  StabilityCase(double v, const Model* m, std::vector<const Model*> lanes = {})
      : value(v), model(m), lane_models(std::move(lanes)) {}
  double value = 0.0;
  const Model* model = nullptr;
  // Per integrators entry, the model that lane searches (nullptr: `model`): a lane's own
  // solver settings (the fixed point, iteration counts) on this case's model. Empty: `model`.
  std::vector<const Model*> lane_models;
};
const Model& case_lane_model(const StabilityCase& c, std::size_t lane);

// A search's rough cost in force-evaluation equivalents, for sharding only (shard.h): the
// search's own trials replayed on the limit predicted_limit gives with the dampers' bound
// c_max / 2.4 (a stable trial runs T / dt steps, an unstable one 0.3 of them), each step
// its evaluations (implicit_euler: 42 x (1 + 5.6e-5 P w_max dt), its frame-step runs added).
// Fitted on the drape (docs/cluster.md); no timing enters it, so every shard agrees.
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
