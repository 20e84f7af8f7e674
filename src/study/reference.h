// The reference of a smooth scene: an adaptive, error-controlled, high-order solve with dense
// output, as work-precision studies compute theirs (DiffEqDevTools / SciMLBenchmarks: an
// adaptive high-order solve at tolerances far below every error shown).
//
// The ODE is the engine's own: y = (x, v), y' = (v, a(x, v)) with a = accelerations() (the
// function every explicit integrator calls), so gravity, drag, springs, scripted sphere
// velocities and any smooth contact force come with it. Timeline actions (pins, unpins, sphere
// velocity keyframes) are discontinuities at known times: the solve stops exactly there, applies
// them and restarts (piecewise between events). It is Dormand & Prince's 5(4) pair (Hairer,
// Norsett & Wanner, Solving ODEs I, II.5) under Boost.Odeint's step-size controller, with its
// 4th-order continuous extension giving the state at any time inside the last step.
//
// Only a smooth scene has such a reference: the projection contact model resolves contacts
// once per step (core/collisions.h), which is a different, step-dependent system. There the
// reference stays a fine fixed-step RK4 run (smooth_scene() decides).
//
// The reference's own error: a second solve at a looser tolerance. Positions are served from the
// tighter one, and the distance between the two bounds the tighter one's error (it is the looser
// one's): the reference's estimated error, which every error shown is judged by. The two solves
// are independent, so they run on two threads.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "core/model/diagnostics.h"
#include "core/model/model.h"
#include "core/run/simulation.h"
#include "core/model/state.h"
#include "study_run.h"

namespace clothsim::analysis {

// Whether the scene's equations of motion are one smooth ODE between its timeline's events: its
// contacts are the barrier's potential (collision.model: barrier), or it has none to resolve by
// projection (no sphere, no ground). The one predicate that chooses the adaptive reference over
// the fixed-step one.
bool smooth_scene(const Model& model);

// compare's reference tolerance (absolute and relative, per coordinate in m and m/s): the check
// solve's; the served one is kCompareTightening tighter. The check's error is the estimate, so
// its tolerance sets what the estimate can be, and the served one only has to be well below it:
// 10x is enough for the distance to bound the served one's error and costs 23 % less than 100x
// on the drape (BENCHMARKS.md). bench, whose errors reach round-off, uses 1e-11 and 100x
// (work_precision.h).
inline constexpr double kReferenceTolerance = 1e-6;
inline constexpr double kCompareTightening = 10.0;
// How much tighter bench's served solve is than its check.
inline constexpr double kReferenceTightening = 100.0;

// One adaptive solve from the scene's initial state.
class AdaptiveSolve {
 public:
  AdaptiveSolve(const Model& model, double tolerance);
  ~AdaptiveSolve();
  AdaptiveSolve(AdaptiveSolve&&) noexcept;

  // Advances to time t (not before the last time asked); state() is then the state at t.
  // False once diverged (a non-finite or runaway state, check_bodies) or stopped.
  bool advance_to(double t);
  void set_stop_check(std::function<bool()> stop);
  bool stopped() const;
  const std::optional<Divergence>& divergence() const;
  const State& state() const;  // at the last time asked (step: the steps taken so far)
  std::int64_t steps() const;  // accepted steps
  std::int64_t force_evals() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The reference: the solve at `tolerance` and at tolerance / tightening, in step (the looser on a
// second thread).
class AdaptiveReference {
 public:
  explicit AdaptiveReference(const Model& model, double tolerance = kReferenceTolerance,
                             double tightening = kCompareTightening);

  // Both solves to t (increasing); the tighter's state is state(), and the largest particle
  // distance between the two there raises estimated_error().
  bool advance_to(double t);
  // Polled by the served solve only (the check solve, on its own thread, stops with it).
  void set_stop_check(const std::function<bool()>& stop);
  bool stopped() const { return tight_.stopped() || loose_.stopped(); }
  bool diverged() const { return divergence().has_value(); }
  const std::optional<Divergence>& divergence() const {
    return tight_.divergence() ? tight_.divergence() : loose_.divergence();
  }
  const State& state() const { return tight_.state(); }
  // s, the last time both solves reached (a stop check polled inside an advance reads this,
  // not the tighter's time, which is ahead of the looser's until the advance ends).
  double time() const { return time_; }
  // m, the largest particle distance between the two solves over every time advanced to.
  double estimated_error() const { return estimated_error_; }
  // m, that distance at the last time advanced to.
  double last_change() const { return last_change_; }
  double tolerance() const { return tolerance_; }  // the check's
  double served_tolerance() const { return tolerance_ / tightening_; }
  // Both solves' work, as a Run's totals count it (steps: the tighter's; force evaluations and
  // CPU seconds: both).
  RunTotals totals() const;

 private:
  const Model& model_;
  double tolerance_, tightening_;
  AdaptiveSolve tight_, loose_;
  std::atomic<bool> abandon_{false};  // the served solve stopped: the check's thread stops too
  double estimated_error_ = 0.0, last_change_ = 0.0, cpu_seconds_ = 0.0, time_ = 0.0;
};

// One adaptive solve to time T as a study's run (study_run.h): finished, stopped or diverged,
// its steps, force evaluations and CPU time, and its state at T.
// `sampling`: the solve's state at each of its times on the way (dense output: it lands on all).
StudyRun adaptive_run_to(const Model& model, double tolerance, double T, const std::function<bool()>& stop = {},
                         const Sampling& sampling = {});

// Largest distance (m) between the free cloth particles of two states (inv_mass > 0 in `b`).
double largest_particle_distance(const Model& model, const State& a, const State& b);

}  // namespace clothsim::analysis
