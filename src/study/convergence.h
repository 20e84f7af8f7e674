// The yardstick for the iterative solvers: how far a few iterations of each are from the step
// they approximate, per iteration and per CPU second (`clothsim converge`, docs/integrators.md).
//
// K states are taken along a converged implicit_euler run of the scene at step h (evenly in
// time, the first after one step); from each, the converged backward-Euler step is the
// reference, and every method takes one step with 1, 2, ..., N iterations. Each point records
// the distance of that step's end positions from the reference (RMS and max over the
// particles, m), the norm of Phi's gradient at them (N s; nonzero at a solution held by
// contacts, whose forces it leaves out) and the step's CPU time. A step with n iterations is
// run afresh for every n, so a study costs about N^2 / 2 iterations per method and state.
#pragma once

#include <functional>
#include <vector>

#include "core/integrators/integrator_kind.h"
#include "core/model.h"

namespace clothsim {

struct ConvergenceSpec {
  double h = 1.0 / 60.0;
  int states = 5;
  int max_iterations = 50;
  std::vector<IntegratorKind> methods;  // xpbd, projective_dynamics, vbd, implicit_euler (Newton cap)
};

struct ConvergencePoint {
  IntegratorKind method{};
  int state = 0;          // 0 .. K-1
  double t = 0.0;         // s, the state's time
  int iterations = 0;
  double rms = 0.0, max = 0.0;  // m, from the converged backward-Euler step
  double gradient = 0.0;        // N s, |grad Phi| at the step's end positions
  double cpu_seconds = 0.0;     // the step's CPU time
};

// `progress(done, total)` is called after each method's sweep from a state.
std::vector<ConvergencePoint> convergence_study(const Model& model, const ConvergenceSpec& spec,
                                                const std::function<void(int, int)>& progress = {});

}  // namespace clothsim
