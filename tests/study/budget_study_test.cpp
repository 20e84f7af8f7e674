// The substeps-iterations study (bench --budget): the grid, what each split costs, the reference
// it is measured against, and Macklin et al. 2019's claim where it holds and where it does not.
#include "study/budget_study.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "study/tables/budget_table.h"
#include "test_support.h"

namespace clothsim::analysis {
namespace {

// A soft sheet over a ball with the barrier (a smooth scene: the adaptive reference), as the
// drape is: its reference strain ~0.07, N = 6 a frame at 60 frames/s.
Model soft_drape() {
  return testing::model_from_yaml(R"(
name: small_drape_smooth
duration: 0.5
dt: 1.0e-3
cloth: {particles: [9, 9], size: [2, 2], center: [0, 0.51, 0], plane: xz, particle_mass: 0.1,
        springs: {structural: {stiffness: 2000, damping: 20}, shear: {stiffness: 2000, damping: 20}},
        pinned: corners}
spheres: [{center: [0, 0, 0], radius: 0.5, kinematic: true}]
collision: {model: barrier, barrier_distance: 0.01, barrier_stiffness: 1.0e5}
)");
}

// A stiff sheet hanging from its corners (ks = 1e6 N/m on 0.1 kg particles: true strain 0.0015),
// Macklin's regime: constraints that a few Gauss-Seidel sweeps cannot converge.
Model stiff_sheet() {
  return testing::model_from_yaml(R"(
name: small_hang
duration: 0.5
dt: 1.0e-3
cloth: {particles: [9, 9], size: [2, 2], center: [0, 0.5, 0], plane: xz, particle_mass: 0.1,
        springs: {structural: {stiffness: 1.0e6}, shear: {stiffness: 1.0e6}},
        pinned: corners}
)");
}

BudgetSpec spec_of(std::vector<IntegratorKind> solvers, int budget = 6) {
  BudgetSpec spec;
  spec.budget = budget;
  spec.fps = 60.0;
  spec.duration = 0.5;
  spec.solvers = std::move(solvers);
  return spec;
}

const BudgetPoint& at(const BudgetResult& r, IntegratorKind kind, int substeps) {
  for (const BudgetPoint& p : r.points)
    if (p.kind == kind && p.substeps == substeps) return p;
  throw std::logic_error("no such split");
}

TEST(BudgetStudy, GridIsEveryDivisorPairOfTheBudget) {
  EXPECT_EQ(divisors(30), (std::vector<int>{1, 2, 3, 5, 6, 10, 15, 30}));
  EXPECT_EQ(divisors(1), (std::vector<int>{1}));
  EXPECT_EQ(divisors(7), (std::vector<int>{1, 7}));
  const std::vector<BudgetPoint> grid = budget_points(spec_of({IntegratorKind::Xpbd, IntegratorKind::Vbd}, 30));
  ASSERT_EQ(grid.size(), 16u);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const BudgetPoint& p = grid[i];
    EXPECT_EQ(p.kind, i < 8 ? IntegratorKind::Xpbd : IntegratorKind::Vbd);
    EXPECT_EQ(p.substeps * p.iterations, 30);
    EXPECT_DOUBLE_EQ(p.dt, 1.0 / (60.0 * p.substeps));
  }
  EXPECT_EQ(grid.front().substeps, 1);
  EXPECT_EQ(grid[7].substeps, 30);
}

TEST(BudgetStudy, RefusesWhatDoesNotFit) {
  const auto refusal = [](BudgetSpec s) {
    try {
      checked(s);
    } catch (const StudyError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  BudgetSpec s = spec_of({IntegratorKind::Xpbd});
  EXPECT_EQ(refusal(s), "");
  s.budget = 0;
  EXPECT_NE(refusal(s).find("from 1 to 1000000"), std::string::npos);
  s = spec_of({IntegratorKind::Rk4});
  EXPECT_NE(refusal(s).find("rk4 takes no iterations"), std::string::npos);
  s = spec_of({IntegratorKind::Xpbd});
  s.duration = 0.51;  // 30.6 frames at 60 frames/s
  EXPECT_NE(refusal(s).find("not a whole number of frames"), std::string::npos);
  s = spec_of({IntegratorKind::Xpbd});
  s.reference_dt = 1.0 / 100.0;  // longer than the smallest step, 1/360 s
  EXPECT_NE(refusal(s).find("reference step"), std::string::npos);
}

TEST(BudgetStudy, OnASoftDrapeTheSmallStepsWinAtEqualSweeps) {
  const Model model = soft_drape();
  const BudgetResult r = budget_study(model, spec_of({IntegratorKind::Vbd, IntegratorKind::ImplicitEuler}));
  ASSERT_TRUE(r.complete);
  ASSERT_EQ(r.points.size(), 8u);
  EXPECT_EQ(r.frames, 30);
  // The reference: the adaptive pair, its own error far below every error it judges.
  ASSERT_TRUE(r.reference.finished);
  EXPECT_TRUE(r.reference.adaptive);
  for (const BudgetPoint& p : r.points) {
    ASSERT_TRUE(p.finished) << p.substeps;
    EXPECT_FALSE(p.unresolved);
    EXPECT_LT(r.reference.estimated_error * 1000, p.max_error);
    EXPECT_EQ(p.frames, 30);
    EXPECT_EQ(p.totals.steps, 30 * p.substeps);  // s steps a frame
    if (p.kind == IntegratorKind::Vbd) EXPECT_EQ(p.totals.solver_iterations, 30 * 6);  // the budget, whatever the split
    else EXPECT_LE(p.totals.newton_iterations, p.totals.steps * p.iterations);  // a cap, not a count
  }
  for (IntegratorKind kind : {IntegratorKind::Vbd, IntegratorKind::ImplicitEuler}) {
    const BudgetPoint &big = at(r, kind, 1), &small = at(r, kind, 6);
    // Error falls with the step at every split (VBD's and Newton's inner error is second to the
    // step's here), so 6 x 1 is closest: under a third of 1 x 6's.
    EXPECT_LT(small.max_error * 3, big.max_error);
    for (int s : {2, 3}) EXPECT_LT(at(r, kind, s).max_error, at(r, kind, s == 2 ? 1 : 2).max_error);
    // What holds of the strain on a soft cloth: 1 x 6 under-stretches (backward Euler's large step
    // damps the fall), 6 x 1 is nearer the reference's largest strain.
    EXPECT_LT(big.max_strain, r.reference.max_strain);
    EXPECT_LT(std::abs(small.max_strain - r.reference.max_strain), std::abs(big.max_strain - r.reference.max_strain));
    const BudgetVerdict v = budget_verdict(r, kind == IntegratorKind::Vbd ? 0 : 1);
    EXPECT_EQ(r.points[v.winner].substeps, 6);
    EXPECT_EQ(r.points[v.against].substeps, 1);
    EXPECT_NE(v.text.find("at N = 6: 6 substeps x 1 "), std::string::npos) << v.text;
    EXPECT_NE(v.text.find(" for 1 x 6, strain "), std::string::npos) << v.text;
  }
  // One CSV row per split, its lane as given.
  const CsvTable t = budget_table(r, std::vector<std::string>(8, "lane"));
  ASSERT_EQ(t.rows.size(), 8u);
  EXPECT_EQ(t.rows[0].size(), t.columns.size());
  EXPECT_EQ(t.columns[0], "solver");
}

TEST(BudgetStudy, OnAStiffSheetXpbdSubstepsStretchLessAsMacklinSays) {
  // Macklin et al. 2019, Fig. 1: 1 substep x N XPBD iterations stretches, N x 1 does not (as
  // much). So for projective dynamics, another local-global solve that few sweeps leave short.
  const Model model = stiff_sheet();
  const BudgetResult r = budget_study(model, spec_of({IntegratorKind::Xpbd, IntegratorKind::ProjectiveDynamics}));
  ASSERT_TRUE(r.complete);
  ASSERT_TRUE(r.reference.finished);
  EXPECT_LT(r.reference.max_strain, 0.002);
  for (IntegratorKind kind : {IntegratorKind::Xpbd, IntegratorKind::ProjectiveDynamics}) {
    double previous = INFINITY;
    for (int s : divisors(6)) {  // every smaller step stretches less
      const BudgetPoint& p = at(r, kind, s);
      ASSERT_TRUE(p.finished);
      EXPECT_LT(p.max_strain, previous) << integrator_name(kind) << " " << s;
      EXPECT_GT(p.max_strain, 2 * r.reference.max_strain);  // and all still stretch
      previous = p.max_strain;
    }
    EXPECT_LT(at(r, kind, 6).max_strain * 2, at(r, kind, 1).max_strain);
  }
}

TEST(BudgetStudy, StopsWhenAskedAndSaysItIsIncomplete) {
  const Model model = soft_drape();
  StudyHooks hooks;
  std::atomic<int> polls{0};  // polled from the reference's and the runs' threads
  hooks.stop = [&] { return ++polls > 200; };
  const BudgetResult r = budget_study(model, spec_of({IntegratorKind::Vbd}), hooks);
  EXPECT_FALSE(r.complete);
}

}  // namespace
}  // namespace clothsim::analysis
