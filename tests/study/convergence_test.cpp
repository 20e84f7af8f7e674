// The convergence study: distances from converged backward Euler per iteration.
#include "study/convergence.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>

#include "core/run/simulation.h"
#include "core/solvers/step_problem.h"
#include "test_support.h"

namespace clothsim {
namespace {

Model small_drape() {
  return testing::model_from_yaml(R"(
name: small_drape
duration: 0.5
dt: 0.0166666666666667
cloth: {particles: [8, 8], size: [2, 2], center: [0, 0.6, 0], plane: xz, particle_mass: 0.2,
        springs: {structural: {stiffness: 2000, damping: 20}, shear: {stiffness: 2000, damping: 20}},
        pinned: none}
spheres: [{center: [0, 0, 0], radius: 0.5, kinematic: true}]
)");
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
