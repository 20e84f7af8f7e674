// The convergence study: distances from converged backward Euler per iteration.
#include "study/convergence.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "core/run/simulation.h"
#include "core/solvers/step_problem.h"
#include "test_support.h"

namespace clothsim {
namespace {

// An 8 x 8 sheet of 2 x 2 m at 0.6 m, its YAML ending in `rest` (pins, spheres).
Model eight_by_eight(const std::string& name, const std::string& rest) {
  return testing::model_from_yaml("name: " + name + R"(
duration: 0.5
dt: 0.0166666666666667
cloth: {particles: [8, 8], size: [2, 2], center: [0, 0.6, 0], plane: xz, particle_mass: 0.2,
        springs: {structural: {stiffness: 2000, damping: 20}, shear: {stiffness: 2000, damping: 20}},
)" + rest);
}

Model small_drape() {
  return eight_by_eight("small_drape", "        pinned: none}\nspheres: [{center: [0, 0, 0], radius: 0.5, kinematic: true}]\n");
}

// The same sheet on the ground as well as the ball, PD with Chebyshev's acceleration on.
Model drape_on_ground_chebyshev() {
  return testing::model_from_yaml(R"(
name: small_drape_ground
duration: 0.5
dt: 0.0166666666666667
cloth: {particles: [6, 6], size: [2, 2], center: [0, 0.3, 0], plane: xz, particle_mass: 0.2,
        springs: {structural: {stiffness: 2000, damping: 20}, bend: {stiffness: 200, damping: 2}},
        pinned: corners}
spheres: [{center: [0, 0, 0], radius: 0.3, kinematic: true}]
ground: {height: 0.0}
projective_dynamics: {chebyshev_rho: 0.9}
)");
}

void set_iterations(Model& m, IntegratorKind kind, int n) {
  if (kind == IntegratorKind::ImplicitEuler) m.implicit.newton_max_iterations = n;
  if (kind == IntegratorKind::Xpbd) m.solvers.xpbd.iterations = n;
  if (kind == IntegratorKind::ProjectiveDynamics) m.solvers.projective_dynamics.iterations = n;
  if (kind == IntegratorKind::Vbd) m.solvers.vbd.iterations = n;
}

// What the study measured before it watched iterations: a fresh step per iteration count n.
std::vector<ConvergencePoint> step_per_count(const Model& model, const ConvergenceSpec& spec, const State& start,
                                             IntegratorKind kind) {
  const State reference = converged_step(model, start, spec.h);
  StepProblem problem;
  build_step_problem(model, start, spec.h, problem);
  Model m = model;
  Workspace ws;
  std::vector<ConvergencePoint> points;
  for (int n = 1; n <= spec.max_iterations; ++n) {
    set_iterations(m, kind, n);
    State s = start;
    step(m, s, kind, spec.h, ws);
    const int P = model.num_particles;
    const Eigen::VectorXd d = (s.x.leftCols(P) - reference.x.leftCols(P)).colwise().norm();
    ConvergencePoint p;
    p.method = kind;
    p.t = start.t;
    p.iterations = n;
    p.rms = std::sqrt(d.squaredNorm() / P);
    p.max = d.maxCoeff();
    Eigen::Matrix3Xd gradient;
    p.gradient = step_gradient(model, problem, s.x, gradient);
    points.push_back(p);
  }
  return points;
}

double distance(const std::vector<ConvergencePoint>& points, IntegratorKind k, int state, int iterations) {
  for (const ConvergencePoint& p : points)
    if (p.method == k && p.state == state && p.iterations == iterations) return p.rms;
  ADD_FAILURE() << "no point";
  return 0.0;
}

TEST(Convergence, EveryMethodGetsCloserToBackwardEulerAndNewtonReachesIt) {
  ConvergenceSpec spec;
  spec.states = 2;
  spec.max_iterations = 30;
  spec.methods = {IntegratorKind::ProjectiveDynamics, IntegratorKind::Vbd, IntegratorKind::Xpbd,
                  IntegratorKind::ImplicitEuler};
  const auto points = convergence_study(small_drape(), spec);
  ASSERT_EQ(points.size(), 2u * 4u * 30u);
  const int last = spec.states - 1;
  for (IntegratorKind k : {IntegratorKind::ProjectiveDynamics, IntegratorKind::Vbd, IntegratorKind::Xpbd})
    EXPECT_LT(distance(points, k, last, 30), distance(points, k, last, 1)) << integrator_name(k);
  EXPECT_LT(distance(points, IntegratorKind::ImplicitEuler, last, 30), 1e-8);
  for (const ConvergencePoint& p : points) {
    EXPECT_GE(p.max, p.rms);
    EXPECT_GE(p.cpu_seconds, 0.0);
  }
}

// The same sheet hung by its corners, clear of everything (no contact: the family's history is
// never reset).
Model free_sheet() { return eight_by_eight("free_sheet", "        pinned: corners}\n"); }

constexpr IntegratorKind kFamily[] = {IntegratorKind::ImplicitMidpoint, IntegratorKind::Newmark,
                                      IntegratorKind::GeneralizedAlpha, IntegratorKind::Bdf2};

// Each of the implicit family, from its own run's states, falls to its own converged step: the
// distance at the cap is the scene's Newton tolerance, far below its first iteration's, on the
// sheet with and without the ball (held in the solve, which restarts the history).
TEST(Convergence, EveryImplicitMethodFallsToItsOwnConvergedStep) {
  for (const Model& model : {free_sheet(), small_drape()}) {
    ConvergenceSpec spec;
    spec.states = 3;
    spec.max_iterations = 12;
    spec.methods.assign(std::begin(kFamily), std::end(kFamily));
    const auto points = convergence_study(model, spec);
    ASSERT_EQ(points.size(), 3u * 4u * 12u);
    for (IntegratorKind k : kFamily)
      for (int state = 0; state < spec.states; ++state) {
        SCOPED_TRACE(model.name + " " + std::string(integrator_name(k)) + " state " + std::to_string(state));
        const double first = distance(points, k, state, 1), capped = distance(points, k, state, 12);
        EXPECT_LT(capped, 1e-8);  // the scene's Newton tolerance, as implicit_euler's above
        EXPECT_LE(capped, first);
        if (first > 1e-8) EXPECT_GT(first, 100.0 * capped);  // (a free fall's first iteration is its step)
      }
    for (const ConvergencePoint& p : points) EXPECT_TRUE(std::isnan(p.gradient)) << "Phi is backward Euler's";
  }
}

// The states come from the method's own run, history and all: bdf2's step before and newmark's
// acceleration carry on, and the reference is the method's step from them, not backward Euler's.
TEST(Convergence, TheFamilysStatesCarryTheirRunsHistoryAndTheReferenceIsItsOwnStep) {
  const Model model = free_sheet();
  ConvergenceSpec spec;
  spec.states = 3;
  for (IntegratorKind k : {IntegratorKind::Newmark, IntegratorKind::Bdf2}) {
    const std::vector<State> states = convergence_states(model, spec, spec.states, {}, k);
    ASSERT_EQ(states.size(), 3u);
    for (const State& s : states) EXPECT_TRUE(s.history.continues(k, s)) << integrator_name(k);
    const State own = converged_step(model, states[2], spec.h, k);
    const State euler = converged_step(model, states[2], spec.h);
    EXPECT_GT((own.x - euler.x).cwiseAbs().maxCoeff(), 1e-6) << integrator_name(k);
    // and the run itself takes that step (to its own tolerance) from that state
    Model run_model = model;
    run_model.implicit.newton_max_iterations = 200;
    State next = states[2];
    Workspace ws;
    step(run_model, next, k, spec.h, ws);
    EXPECT_LT((next.x - own.x).cwiseAbs().maxCoeff(), 1e-6) << integrator_name(k);
  }
}

// One step of N iterations watched at each is the steps of 1..N iterations, bit for bit, for
// every method (Newton's by a step per cap until one ends short of it), with and without
// contacts, the ground and Chebyshev's acceleration.
TEST(Convergence, OneWatchedStepEqualsAStepPerIterationCount) {
  for (const Model& model : {small_drape(), drape_on_ground_chebyshev()}) {
    ConvergenceSpec spec;
    spec.states = 2;
    spec.max_iterations = 14;
    spec.methods = {IntegratorKind::Xpbd, IntegratorKind::ProjectiveDynamics, IntegratorKind::Vbd,
                    IntegratorKind::ImplicitEuler};
    const auto points = convergence_study(model, spec);
    ASSERT_EQ(points.size(), 2u * 4u * 14u);
    const std::vector<State> states = convergence_states(model, spec, spec.states);
    std::size_t at = 0;
    for (int k = 0; k < spec.states; ++k)
      for (IntegratorKind kind : spec.methods)
        for (const ConvergencePoint& expected : step_per_count(model, spec, states[k], kind)) {
          const ConvergencePoint& p = points[at++];
          SCOPED_TRACE(model.name + " " + std::string(integrator_name(kind)) + " state " + std::to_string(k) +
                       ", " + std::to_string(expected.iterations) + " iterations");
          ASSERT_EQ(p.method, kind);
          ASSERT_EQ(p.state, k);
          ASSERT_EQ(p.iterations, expected.iterations);
          EXPECT_EQ(p.rms, expected.rms);
          EXPECT_EQ(p.max, expected.max);
          EXPECT_EQ(p.gradient, expected.gradient);
        }
  }
}

// The items are the rows' order, and the study stops between items when asked.
TEST(Convergence, ItemsAreStatesTimesMethodsAndAStopKeepsFinishedItemsOnly) {
  ConvergenceSpec spec;
  spec.states = 3;
  spec.max_iterations = 4;
  spec.methods = {IntegratorKind::Vbd, IntegratorKind::ImplicitEuler};
  const auto items = convergence_items(spec);
  ASSERT_EQ(items.size(), 6u);
  EXPECT_EQ(items[3].state, 1);
  EXPECT_EQ(items[3].method, IntegratorKind::ImplicitEuler);
  EXPECT_GT(convergence_item_cost(spec, items[1]), convergence_item_cost(spec, items[0]));
  int finished = 0;
  analysis::StudyHooks hooks;
  hooks.stop = [&] { return finished >= 1; };
  const bool complete = run_convergence_items(small_drape(), spec, {1, 4, 5}, hooks,
                                              [&](std::size_t item, const std::vector<ConvergencePoint>& p) {
                                                EXPECT_EQ(item, 1u);
                                                EXPECT_EQ(p.size(), 4u);
                                                ++finished;
                                              });
  EXPECT_FALSE(complete);
  EXPECT_EQ(finished, 1);
}

// A shard runs some items from the states it samples itself: its rows are the whole study's.
TEST(Convergence, ItemsRunApartGiveTheWholeStudysRows) {
  ConvergenceSpec spec;
  spec.states = 2;
  spec.max_iterations = 3;
  spec.methods = {IntegratorKind::Xpbd, IntegratorKind::ImplicitEuler};
  const Model model = small_drape();
  const auto whole = convergence_study(model, spec);
  std::vector<ConvergencePoint> apart;
  for (std::vector<std::size_t> part : {std::vector<std::size_t>{0, 3}, {1, 2}})
    run_convergence_items(model, spec, part, {}, [&](std::size_t item, const std::vector<ConvergencePoint>& p) {
      std::copy(p.begin(), p.end(), std::back_inserter(apart));
      EXPECT_EQ(p.front().state, static_cast<int>(item / 2));
    });
  ASSERT_EQ(apart.size(), whole.size());
  for (const ConvergencePoint& p : apart) {
    const auto same = std::find_if(whole.begin(), whole.end(), [&](const ConvergencePoint& w) {
      return w.method == p.method && w.state == p.state && w.iterations == p.iterations;
    });
    ASSERT_NE(same, whole.end());
    EXPECT_EQ(same->rms, p.rms);
    EXPECT_EQ(same->gradient, p.gradient);
  }
}

}  // namespace
}  // namespace clothsim
