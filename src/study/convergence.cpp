#include "convergence.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include "core/run/simulation.h"
#include "core/solvers/step_problem.h"

namespace clothsim {
namespace {

// The reference's solve: converged hard (the point is the distance from the solution).
MethodSettings reference_settings(const Model& model) {
  MethodSettings s = model.method_defaults();
  s.implicit.solver = ImplicitSolver::Newton;
  s.implicit.newton_tolerance = std::min(s.implicit.newton_tolerance, 1e-10);
  s.implicit.newton_max_iterations = std::max(s.implicit.newton_max_iterations, 200);
  return s;
}

// The run the states are taken from: Newton converged as a run converges it (the scene's
// tolerance), which is half the reference's cost at 64 x 64; the states are start points only.
MethodSettings sampling_settings(const Model& model) {
  MethodSettings s = model.method_defaults();
  s.implicit.solver = ImplicitSolver::Newton;
  s.implicit.newton_max_iterations = std::max(s.implicit.newton_max_iterations, 200);
  return s;
}

// Iteration counts exactly: a scene's residual tolerance would stop a watched sweep short.
void without_tolerances(MethodSettings& s) {
  s.solvers.xpbd.tolerance = s.solvers.projective_dynamics.tolerance = s.solvers.vbd.tolerance = 0.0;
}

// Rough spring passes of one iteration (a solver's registry row; a Newton iteration, about
// 25), and of measuring a point (its end of step, its distance and Phi's gradient).
constexpr double kNewtonPasses = 25.0;
double passes_per_iteration(IntegratorKind kind) {
  const IntegratorInfo& info = integrator_info(kind);
  return info.iterations == IterationControl::Solver ? info.passes_per_iteration : kNewtonPasses;
}
constexpr double kMeasurePasses = 3.0;
constexpr int kTypicalNewtonIterations = 8;

// One state's start: the state, its step problem (backward Euler's, for Phi's gradient and for
// ending a watched step) and the converged step from it (backward Euler's, or the family
// method's own).
struct Start {
  int index = 0;
  State state;
  StepProblem problem;
  State reference;
  double energy = 0.0;        // J, the state's total energy
  double scene_strain = 0.0;  // the largest strain the scene starts with (WRONG's offset)
};

// `source`'s start (states_source): the reference is its converged step.
Start make_start(const Model& model, const ConvergenceSpec& spec, int index, State state, IntegratorKind source) {
  Start s;
  s.index = index;
  s.reference = converged_step(model, state, spec.h, source);
  build_step_problem(model, state, spec.h, s.problem);
  s.energy = compute_energies(model, state).total();
  s.scene_strain = max_strain(model, initial_state(model));
  s.state = std::move(state);
  return s;
}

ConvergencePoint measured(const Model& model, const Start& s, IntegratorKind method, int iterations,
                          const State& end) {
  ConvergencePoint p;
  p.method = method;
  p.state = s.index;
  p.t = s.state.t;
  p.iterations = iterations;
  const int P = model.num_particles;
  const Eigen::VectorXd d = (end.x.leftCols(P) - s.reference.x.leftCols(P)).colwise().norm();
  p.rms = std::sqrt(d.squaredNorm() / P);
  p.max = d.maxCoeff();
  Eigen::Matrix3Xd gradient;  // backward Euler's Phi: not the family's potential
  p.gradient = states_source(method) == kBackwardEuler ? step_gradient(model, s.problem, end.x, gradient)
                                                       : std::numeric_limits<double>::quiet_NaN();
  // WRONG (core/diagnostics.h) over the one step: energy made while nothing did work, or strain.
  EnergyLedger ledger;
  record_energy(ledger, s.energy, true);
  record_energy(ledger, compute_energies(model, end).total(), external_work(model, s.state));
  auto wrong = check_energy_made(model, ledger, end.step, end.t);
  if (!wrong) wrong = check_over_stretched(max_strain(model, end), s.scene_strain, end.step, end.t);
  if (wrong) p.wrong = wrong->reason;
  return p;
}

// The step ended at iterate y as step() ends it: v = (y - x_n) / h, x = y, then the contact
// response (positions only are measured; time and events move no particle).
State ended_at(const Model& model, const Start& s, const Eigen::Matrix3Xd& y) {
  State end = s.state;
  finish_step(s.problem, y, end);
  resolve_collisions(model, end);
  return end;
}

// xpbd, projective_dynamics, vbd: one step of N iterations, every iteration measured with the
// thread's CPU clock paused. A point's CPU is the step's up to that iteration plus the step's
// end (what a step of n iterations costs). The caches (a factor, a colouring) are warmed first
// by a step of one iteration, as a run's first step warms them for the rest.
std::vector<ConvergencePoint> watched_sweep(const Model& model, const ConvergenceSpec& spec, const Start& s,
                                            IntegratorKind method) {
  MethodSettings m = model.method_defaults();
  Workspace ws;
  without_tolerances(m);
  *iteration_count(m, method) = 1;
  State warm = s.state;
  step(model, m, warm, method, spec.h, ws);
  *iteration_count(m, method) = spec.max_iterations;
  std::vector<ConvergencePoint> points(static_cast<std::size_t>(spec.max_iterations));
  double start = 0.0, paused = 0.0;
  ws.on_iteration = [&](int n, const Eigen::Matrix3Xd& y) {
    const double at = thread_cpu_seconds();
    ConvergencePoint& p = points[static_cast<std::size_t>(n - 1)];
    p = measured(model, s, method, n, ended_at(model, s, y));
    p.cpu_seconds = at - start - paused;
    paused += thread_cpu_seconds() - at;
  };
  State end = s.state;
  start = thread_cpu_seconds();
  step(model, m, end, method, spec.h, ws);
  for (const ConvergencePoint& p : points)  // every iteration told: a solver that stops early breaks the sweep
    if (p.iterations == 0) throw std::logic_error(std::string(integrator_name(method)) + " skipped an iteration");
  const double tail = thread_cpu_seconds() - start - paused - points.back().cpu_seconds;
  for (ConvergencePoint& p : points) p.cpu_seconds += tail;
  return points;
}

// Capped Newton (implicit_euler, or one of the family from its own run's state and history): a
// step per cap n, until one ends kNewtonSlack short of its cap (every larger cap takes that same
// step, so its point stands for theirs). Empty when `stop` fired.
std::vector<ConvergencePoint> newton_sweep(const Model& model, const ConvergenceSpec& spec, const Start& s,
                                           IntegratorKind method, const std::function<bool()>& stop) {
  MethodSettings m = model.method_defaults();
  m.implicit.solver = ImplicitSolver::Newton;
  Workspace ws;
  State warm = s.state;
  step(model, m, warm, method, spec.h, ws);  // warm the caches
  std::vector<ConvergencePoint> points;
  bool settled = false;
  for (int n = 1; n <= spec.max_iterations; ++n) {
    if (settled) {
      points.push_back(points.back());
      points.back().iterations = n;
      continue;
    }
    if (stop && stop()) return {};
    *iteration_count(m, method) = n;
    State end = s.state;
    const double cpu = thread_cpu_seconds();
    const StepReport report = step(model, m, end, method, spec.h, ws);
    const double spent = thread_cpu_seconds() - cpu;
    points.push_back(measured(model, s, method, n, end));
    points.back().cpu_seconds = spent;
    settled = report.stats.newton_iterations + kNewtonSlack <= n;
  }
  return points;
}

}  // namespace

IntegratorKind states_source(IntegratorKind method) {
  return is_iterative_solver(method) ? kBackwardEuler : method;
}

std::vector<ConvergenceItem> convergence_items(const ConvergenceSpec& spec) {
  std::vector<ConvergenceItem> items;
  for (int k = 0; k < spec.states; ++k)
    for (IntegratorKind method : spec.methods) items.push_back({k, method});
  return items;
}

double convergence_item_cost(const ConvergenceSpec& spec, const ConvergenceItem& item) {
  const double n = spec.max_iterations;
  if (is_iterative_solver(item.method))
    return n * (passes_per_iteration(item.method) + kMeasurePasses);
  const double reruns = std::min(n, static_cast<double>(kTypicalNewtonIterations + kNewtonSlack));
  return passes_per_iteration(item.method) * reruns * (reruns + 1.0) / 2.0 + reruns * kMeasurePasses;
}

std::vector<State> convergence_states(const Model& model, const ConvergenceSpec& spec, int count,
                                      const std::function<bool()>& stop, IntegratorKind source) {
  const MethodSettings sampling = sampling_settings(model);
  const long steps = std::max<long>(1, std::lround(model.duration / spec.h));
  std::vector<State> states;
  State s = initial_state(model);
  Workspace ws;
  for (int i = 0; i < count; ++i) {
    const long at = std::max<long>(1, steps * i / spec.states);
    while (s.step < at) {
      if (stop && stop()) return {};
      step(model, sampling, s, source, spec.h, ws);
    }
    states.push_back(s);
  }
  return states;
}

State converged_step(const Model& model, const State& start, double h, IntegratorKind method) {
  const MethodSettings reference = reference_settings(model);
  State end = start;
  Workspace ws;
  step(model, reference, end, method, h, ws);
  return end;
}

bool run_convergence_items(const Model& model, const ConvergenceSpec& spec, const std::vector<std::size_t>& items,
                           const analysis::StudyHooks& hooks, const ConvergenceItemDone& finished) {
  const std::vector<ConvergenceItem> all = convergence_items(spec);
  if (items.empty()) return true;
  const int count = all[items.back()].state + 1;
  // Per source run (states_source): its states, sampled when an item first needs them, and the
  // start of the state its items are at (items run state by state, so one each suffices).
  std::map<IntegratorKind, std::vector<State>> states;
  std::map<IntegratorKind, Start> starts;
  long done = 0;
  for (std::size_t item : items) {
    if (hooks.stop && hooks.stop()) return false;
    const ConvergenceItem& it = all[item];
    const IntegratorKind source = states_source(it.method);
    std::vector<State>& along = states[source];
    if (along.empty()) along = convergence_states(model, spec, count, hooks.stop, source);
    if (along.empty()) return false;
    auto [at, fresh] = starts.try_emplace(source);
    Start& start = at->second;
    if (fresh || start.index != it.state)
      start = make_start(model, spec, it.state, along[static_cast<std::size_t>(it.state)], source);
    const std::vector<ConvergencePoint> points = is_iterative_solver(it.method)
                                                     ? watched_sweep(model, spec, start, it.method)
                                                     : newton_sweep(model, spec, start, it.method, hooks.stop);
    if (points.empty()) return false;
    finished(item, points);
    if (hooks.progress) hooks.progress(analysis::StudyProgress{++done, static_cast<long>(items.size())});
  }
  return true;
}

std::vector<ConvergencePoint> convergence_study(const Model& model, const ConvergenceSpec& spec,
                                                const analysis::StudyHooks& hooks) {
  std::vector<std::size_t> items(convergence_items(spec).size());
  for (std::size_t i = 0; i < items.size(); ++i) items[i] = i;
  std::vector<ConvergencePoint> points;
  run_convergence_items(model, spec, items, hooks, [&](std::size_t, const std::vector<ConvergencePoint>& item_points) {
    points.insert(points.end(), item_points.begin(), item_points.end());
  });
  return points;
}

}  // namespace clothsim
