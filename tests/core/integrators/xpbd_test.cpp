#include "solver_support.h"

#include "core/solvers/xpbd_kernels.h"

namespace clothsim::testing {
namespace {

constexpr double kH = 1.0 / 60.0;
const IntegratorKind kXpbd = IntegratorKind::Xpbd;

TEST(Xpbd, AStiffConstraintBetweenEqualMassesReachesItsLengthInOneProjection) {
  Vec3 a(0, 0, 0), b(2, 0, 0);
  solve_distance_constraint(a, b, a, b, 1.0, 1.0, 1.0, 1e12, 0.0, kH, 0.0);
  EXPECT_NEAR((a - b).norm(), 1.0, 1e-6);
  EXPECT_NEAR(a.x(), 0.5, 1e-6);  // each end moves half the way
}

TEST(Xpbd, AContactMovesOutByItsDepthAndStaticFrictionHoldsTheSlide) {
  Vec3 y(0.01, -0.1, 0.0);
  solve_contact_constraint(y, Vec3(0, 0.5, 0), kH, Penetration{Vec3::UnitY(), 0.1, 1.0, Vec3::Zero()});
  EXPECT_NEAR(y.y(), 0.0, 1e-12);
  EXPECT_NEAR(y.x(), 0.0, 1e-12);  // slide 0.01 < mu depth 0.1: cancelled
}

TEST(Xpbd, ReachesItsOwnConstraintSolution) {
  const Model model = free_sheet();
  const State start = random_state(model, 5);
  const State at1000 = one_step(with_iterations(model, kXpbd, 1000), start, kXpbd, kH);
  const State at4000 = one_step(with_iterations(model, kXpbd, 4000), start, kXpbd, kH);
  EXPECT_LT(relative_distance(at1000, at4000, start), 1e-9);
}

// Its fixed point keeps no geometric stiffness and damps u . v at the end of the step: on
// the free sheet at 1/60 s it lies 1-5 % of the step's motion from backward Euler
// (docs/integrators.md), however many iterations.
TEST(Xpbd, ItsSolutionLiesAFewPercentFromBackwardEuler) {
  const Model model = free_sheet();
  for (unsigned seed : {1u, 2u, 3u}) {
    const State start = random_state(model, seed);
    const State be = one_step(model, start, IntegratorKind::ImplicitEuler, kH);
    const double d = relative_distance(one_step(with_iterations(model, kXpbd, 2000), start, kXpbd, kH), be, start);
    EXPECT_GT(d, 0.005) << "seed " << seed;
    EXPECT_LT(d, 0.05) << "seed " << seed;
  }
}

TEST(Xpbd, StaysFiniteOnTheStiffSceneAtOneThirtiethOfASecond) {
  expect_finite_run(scene_path("stiff.yaml"), kXpbd, 1.0 / 30.0);
}

TEST(Xpbd, SubstepsAreSmallerStepsOfOneIteration) {
  const Model model = with_iterations(free_sheet(), kXpbd, 1);
  clothsim::Run run(model, kXpbd, 1.0 / 600.0);
  run.advance_to(0.1);
  EXPECT_EQ(run.totals().steps, 60);
  EXPECT_EQ(run.totals().newton_iterations, 60);
}

}  // namespace
}  // namespace clothsim::testing
