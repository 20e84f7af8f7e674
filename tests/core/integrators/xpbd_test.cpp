#include "solver_support.h"

#include <Eigen/LU>
#include <algorithm>
#include <cstdio>
#include <set>

#include "core/solvers/solver_cache.h"
#include "core/solvers/xpbd_kernels.h"
#include "core/kernel_test_support.h"

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

// Backward Euler's force imbalance with the textbook damper (as grad_y G, step_problem.h, with
// (kd/h)(l - ln) u replaced by kd u u^T (v_a - v_b), u at y, v = (y - x_n)/h), no contacts.
void textbook_imbalance(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& r) {
  const int B = model.num_bodies();
  r.resize(3, B);
  for (int i = 0; i < B; ++i) r.col(i) = p.weight[i] * (y.col(i) - p.target.col(i));
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Vec3 d = y.col(s.a[k]) - y.col(s.b[k]);
    const double l = d.norm();
    const Vec3 u = d / l;
    const double moved = u.dot((y.col(s.a[k]) - p.start.col(s.a[k])) - (y.col(s.b[k]) - p.start.col(s.b[k])));
    const Vec3 f = (s.ks[k] * (l - s.rest[k]) + (s.kd[k] / p.h) * moved) * u;
    r.col(s.a[k]) += f;
    r.col(s.b[k]) -= f;
  }
}

// Backward Euler with the textbook damper, solved by Newton with a dense finite-difference
// Jacobian: small sheets only.
State textbook_backward_euler(const Model& model, const State& start, double h) {
  StepProblem p;
  build_step_problem(model, start, h, p);
  std::vector<int> free;
  for (int i = 0; i < model.num_bodies(); ++i)
    if (p.weight[i] > 0.0) free.push_back(i);
  const int n = 3 * static_cast<int>(free.size());
  Eigen::Matrix3Xd y = p.target, r;
  const auto residual = [&](const Eigen::Matrix3Xd& at) {
    textbook_imbalance(model, p, at, r);
    Eigen::VectorXd f(n);
    for (std::size_t k = 0; k < free.size(); ++k) f.segment<3>(3 * static_cast<Eigen::Index>(k)) = r.col(free[k]);
    return f;
  };
  for (int it = 0; it < 20; ++it) {
    const Eigen::VectorXd f = residual(y);
    Eigen::MatrixXd J(n, n);
    for (int c = 0; c < n; ++c) {
      const double eps = 1e-7;
      Eigen::Matrix3Xd up = y, down = y;
      up(c % 3, free[c / 3]) += eps;
      down(c % 3, free[c / 3]) -= eps;
      J.col(c) = (residual(up) - residual(down)) / (2 * eps);
    }
    const Eigen::VectorXd dy = J.partialPivLu().solve(-f);
    for (std::size_t k = 0; k < free.size(); ++k) y.col(free[k]) += dy.segment<3>(3 * static_cast<Eigen::Index>(k));
    if (dy.norm() < 1e-14) break;
  }
  State end = start;
  finish_step(p, y, end);
  return end;
}

// What XPBD's gap from backward Euler is made of (docs/integrators.md, "XPBD's gap"): part of
// it is the damper's form (backward Euler with the textbook damper rate u . (v_a - v_b) is
// nearer than clothsim's), and part is not (with every damper off the gap stays: each
// projection moves along its constraint's gradient at its own iterate). Prints the distances
// the docs quote.
TEST(Xpbd, ItsGapIsTheDampersFormAndItsProjectionsOwnGradients) {
  const Model model = free_sheet();
  const Model undamped = free_sheet({"cloth.springs.structural.damping=0", "cloth.springs.shear.damping=0",
                                     "cloth.springs.bend.damping=0"});
  double textbook = 0.0, clothsims = 0.0, off = 0.0;
  for (unsigned seed : {1u, 2u, 3u}) {
    const State start = random_state(model, seed);
    const State xpbd = one_step(with_iterations(model, kXpbd, 4000), start, kXpbd, kH);
    textbook = std::max(textbook, relative_distance(xpbd, textbook_backward_euler(model, start, kH), start));
    clothsims = std::max(clothsims, relative_distance(xpbd, one_step(model, start, IntegratorKind::ImplicitEuler, kH), start));
    const State still = random_state(undamped, seed);
    off = std::max(off, relative_distance(one_step(with_iterations(undamped, kXpbd, 4000), still, kXpbd, kH),
                                          one_step(undamped, still, IntegratorKind::ImplicitEuler, kH), still));
  }
  std::printf("converged xpbd from: textbook-damper backward Euler %.2g, clothsim's %.2g; dampers off: %.2g\n",
              textbook, clothsims, off);
  EXPECT_LT(textbook, 0.75 * clothsims);
  EXPECT_GT(off, 0.005);
}

// The SIMD sweep projects each family's sets in turn: no set may hold a particle twice, or its
// vector stores would lose an update. On odd and even grids, every spring in exactly one set.
TEST(Xpbd, EachFamilySetHoldsEveryParticleAtMostOnce) {
  for (const char* side : {"[9,9]", "[10,7]"}) {
    const Model model = free_sheet({std::string("cloth.particles=") + side});
    State s = initial_state(model);
    Workspace ws;
    step(model, s, kXpbd, kH, ws);
    const XpbdFamilies& f = solver_cache(ws).xpbd;
    const auto& families = model.spring_layout.families;
    ASSERT_EQ(f.runs.size(), 2 * families.size());
    std::size_t springs = 0;
    for (std::size_t k = 0; k < f.runs.size(); ++k) {
      const SpringFamily& fam = families[k / 2];
      std::set<int> seen;
      for (const auto& [k0, k1] : f.runs[k])
        for (std::size_t q = k0; q < k1; ++q) {
          if (fam.rest[q] == 0.0) continue;
          ++springs;
          EXPECT_TRUE(seen.insert(fam.first + static_cast<int>(q)).second) << side << " set " << k;
          EXPECT_TRUE(seen.insert(fam.first + static_cast<int>(q) + fam.offset).second) << side << " set " << k;
        }
    }
    EXPECT_EQ(springs, model.springs.size()) << side;
  }
}

// Sets in turn, or the spring list in its order: another Gauss-Seidel order. XPBD's converged
// iterate depends on the order (each projection moves along the gradient at its own iterate),
// so the two differ, by much less than either lies from backward Euler.
TEST(Xpbd, TheFamilySweepLandsNearTheSpringListsSolution) {
  const Model model = with_iterations(free_sheet(), kXpbd, 3000);
  Model listed = model;
  listed.spring_layout = SpringLayout{};
  for (unsigned seed : {1u, 2u, 3u}) {
    const State start = random_state(model, seed);
    const State families = one_step(model, start, kXpbd, kH), list = one_step(listed, start, kXpbd, kH);
    const State be = one_step(model, start, IntegratorKind::ImplicitEuler, kH);
    const double apart = relative_distance(families, list, start);
    EXPECT_LT(apart, 0.5 * relative_distance(list, be, start)) << "seed " << seed;
  }
}

// A set's projections are independent, so every lane count (by lanes, by pairs, by masked runs
// on one lane) must give the same bits; odd and even rows put the pairs' phase both ways.
TEST(Xpbd, TheFamilySweepGivesTheSameBitsOnEveryHighwayTarget) {
  for (const char* side : {"[9,9]", "[10,7]"}) {
    const Model model = with_iterations(free_sheet({std::string("cloth.particles=") + side}), kXpbd, 7);
    const State start = random_state(model, 5);
    State first;
    RecordProperty("targets", for_each_highway_target([&](const char* target) {
      const State s = one_step(model, start, kXpbd, kH);
      if (first.x.size() == 0) first = s;
      EXPECT_TRUE(s.x == first.x && s.v == first.v) << side << " on " << target;
    }));
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

TEST(Xpbd, FrictionDragsTheClothAlongTheBallsPushAsBackwardEulerDoes) {
  expect_friction_drags_the_cloth_as_backward_euler_does(kXpbd);
}

TEST(Xpbd, StopsOnItsResidualAndSaysWhenItsCapCameFirst) {
  expect_residual_stop(kXpbd, "xpbd");
}

}  // namespace
}  // namespace clothsim::testing
