#include "solver_support.h"

#include "core/solvers/solver_cache.h"

namespace clothsim::testing {
namespace {

constexpr double kH = 1.0 / 60.0;
const IntegratorKind kVbd = IntegratorKind::Vbd;

TEST(Vbd, ReachesTheConvergedBackwardEulerStepWithoutContact) {
  expect_reaches_backward_euler_without_contact(kVbd, kH);
}

TEST(Vbd, ReachesTheConvergedBackwardEulerStepOnTheDrapeWithContactToItsPenalty) {
  Model model = build_model(load_scene(scene_path("drape.yaml")));
  model.implicit.newton_tolerance = 1e-12;
  model.implicit.newton_max_iterations = 200;
  clothsim::Run run(model, IntegratorKind::ImplicitEuler, kH);
  run.advance_to(0.9);  // the cloth lies on the ball
  const State& start = run.state();
  const State be = one_step(model, start, IntegratorKind::ImplicitEuler, kH);
  const double at100 = relative_distance(one_step(with_iterations(model, kVbd, 100), start, kVbd, kH), be, start);
  const double at10000 = relative_distance(one_step(with_iterations(model, kVbd, 10000), start, kVbd, kH), be, start);
  EXPECT_LT(at10000, at100);
  EXPECT_LT(at10000, 1e-3);  // a penalty k_c = 1e4 a_i: contacts sink by F / k_c
}

// The grid's nine colours (i mod 3, j mod 3): no spring may join two vertices of one colour,
// or a vector of them would move both ends at once.
TEST(Vbd, NoSpringJoinsTwoVerticesOfOneGridColour) {
  for (const char* side : {"[9,9]", "[10,7]"}) {
    const Model model = free_sheet({std::string("cloth.particles=") + side});
    State s = initial_state(model);
    Workspace ws;
    step(model, s, kVbd, kH, ws);
    const VbdGrid& g = solver_cache(ws).vbd_grid;
    ASSERT_EQ(g.index.size(), static_cast<std::size_t>(model.num_particles)) << side;
    for (std::size_t k = 0; k < model.springs.size(); ++k)
      EXPECT_NE(g.index[model.springs.a[k]] / g.block, g.index[model.springs.b[k]] / g.block) << side << " spring " << k;
  }
}

// The SIMD sweep over the grid's colours and the scalar one over the greedy colouring of the
// spring graph (a model without a layout) are two Gauss-Seidel orders with one fixed point, G's
// minimiser: far apart after one sweep, together when converged.
TEST(Vbd, TheGridSweepConvergesToTheSpringGraphSweepsStep) {
  const Model model = free_sheet();
  Model listed = model;
  listed.spring_layout = SpringLayout{};
  const State start = random_state(model, 8);
  const auto apart = [&](int n) {
    return relative_distance(one_step(with_iterations(model, kVbd, n), start, kVbd, kH),
                             one_step(with_iterations(listed, kVbd, n), start, kVbd, kH), start);
  };
  EXPECT_GT(apart(1), 1e-4);
  EXPECT_LT(apart(2000), 1e-9);
}

TEST(Vbd, NeverRaisesEnergyWithoutExternalWork) {
  // Converged enough: at the default 10 iterations an iterate is not yet a minimiser and the
  // energy can rise (docs/integrators.md).
  expect_no_energy_gain(with_iterations(free_sheet(), kVbd, 200), kVbd, 1.0 / 30.0);
}

TEST(Vbd, StaysFiniteOnTheStiffSceneAtOneThirtiethOfASecond) {
  expect_finite_run(scene_path("stiff.yaml"), kVbd, 1.0 / 30.0);
}

}  // namespace
}  // namespace clothsim::testing
