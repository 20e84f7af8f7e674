// The yardstick for the iterative methods: how far a few iterations of each are from the step
// they approximate, per iteration and per CPU second (`clothsim converge`, docs/integrators.md).
//
// K states are taken along a converged run of the scene at step h (evenly in time, the first
// after one step); from each, the converged step is the reference, and every method takes one
// step with 1, 2, ..., N iterations. The solvers (xpbd, projective_dynamics, vbd) approximate
// backward Euler's step, and capped implicit_euler is backward Euler, so their states come from
// an implicit_euler run and their reference is its step converged; each of the implicit family
// (implicit_midpoint, newmark, generalized_alpha, bdf2: integrators/implicit_family.h) iterates
// Newton toward its own step, so its states come from a run of that method, carrying the
// history that run left (bdf2's step before, the alpha methods' acceleration: State::history),
// and its reference is its own step from them, converged. Each point records the distance of
// that step's end positions from the reference (RMS and max over the particles, m), the norm of
// backward Euler's Phi gradient at them (N s; nonzero at a solution held by contacts, whose
// forces it leaves out; NaN for the family, whose potential is its own), the step's CPU time and
// whether it reads WRONG (energy made with no work done, or strain past its bound:
// core/diagnostics.h, over the one step).
//
// xpbd, projective_dynamics and vbd take one step of N iterations, watched after every
// iteration (Workspace::on_iteration): their iteration n of N is the step with n iterations,
// since nothing in them depends on N (no stopping rule; Chebyshev's weights depend on n alone).
// Capped Newton (implicit_euler and the family) is not watched: its cap steers it (a reused
// Newton matrix must leave two exact iterations in the budget; at the cap its active-set rounds
// end it; a cap of 1 is the single linearised step), so its step with n iterations is run afresh
// for every n, until one ends kNewtonSlack short of its cap: every larger cap takes that same
// step. So a study costs about N iterations per solver and state, and (m + 2)^2 / 2 for Newton
// converging in m.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "core/model/state.h"
#include "study.h"

namespace clothsim {

struct ConvergenceSpec {
  double h = 1.0 / 60.0;
  int states = 5;
  int max_iterations = 50;
  std::vector<IntegratorKind> methods;  // xpbd, projective_dynamics, vbd, implicit_euler and the family (Newton cap)
};

struct ConvergencePoint {
  IntegratorKind method{};
  int state = 0;          // 0 .. K-1
  double t = 0.0;         // s, the state's time
  int iterations = 0;
  double rms = 0.0, max = 0.0;  // m, from the method's converged step (backward Euler's for the solvers)
  double gradient = 0.0;        // N s, |grad Phi| at the step's end positions (NaN for the implicit family)
  double cpu_seconds = 0.0;     // the step's CPU time (of the thread; measuring excluded)
  std::string wrong;            // why the step reads WRONG (core/diagnostics.h), "" when it does not
};

// A Newton step of m iterations under a cap of m + 2 or more took the same step as under any
// larger cap: each of its directions saw more than 2 iterations left in the budget, all a
// reused matrix asks (newton_solve.cpp, kReuseReserve), and none reached the cap.
inline constexpr int kNewtonSlack = 2;

// The study's work items, one sweep of 1..N iterations each: item k * methods + m is state k
// and spec.methods[m], the order of the rows.
struct ConvergenceItem {
  int state = 0;
  IntegratorKind method{};
};
std::vector<ConvergenceItem> convergence_items(const ConvergenceSpec& spec);
// Rough cost of an item in spring passes, for the shard split only.
double convergence_item_cost(const ConvergenceSpec& spec, const ConvergenceItem& item);

// The method whose run makes `method`'s states: implicit_euler for the solvers and for itself,
// the method itself for the implicit family.
IntegratorKind states_source(IntegratorKind method);

// The first `count` of the K start states (count <= K), along the converged run of `source`
// (states_source). Empty when `stop` returned true first.
std::vector<State> convergence_states(const Model& model, const ConvergenceSpec& spec, int count,
                                      const std::function<bool()>& stop = {},
                                      IntegratorKind source = kBackwardEuler);
// The reference: `start` after one step of `method` converged to 1e-10 (backward Euler for the
// solvers; the method's own step, from the history `start` carries, for the family).
State converged_step(const Model& model, const State& start, double h, IntegratorKind method = kBackwardEuler);

// Runs `items` (ascending indices into convergence_items(spec)), telling `finished` of each
// item's N points as it completes. Returns false when hooks.stop ended it before the last.
using ConvergenceItemDone = std::function<void(std::size_t item, const std::vector<ConvergencePoint>& points)>;
bool run_convergence_items(const Model& model, const ConvergenceSpec& spec, const std::vector<std::size_t>& items,
                           const analysis::StudyHooks& hooks, const ConvergenceItemDone& finished);

// Every item's points, in item order (those of the items finished, when hooks.stop fired).
std::vector<ConvergencePoint> convergence_study(const Model& model, const ConvergenceSpec& spec,
                                                const analysis::StudyHooks& hooks = {});

}  // namespace clothsim
