// Work units: what a run cost, counted the same on every machine.
#include "core/run/work_units.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace clothsim;

namespace {

const char* kSheet = R"(
name: sheet
dt: 1.0e-3
cloth: {particles: [5, 5], size: [1, 1], pinned: corners,
        springs: {structural: {stiffness: 20000, damping: 5}, shear: {stiffness: 20000, damping: 5}}}
)";

}  // namespace

TEST(WorkUnits, AnExplicitRunCostsItsForceEvaluations) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  clothsim::Run run(model, IntegratorKind::Rk4, 1e-3);
  run.advance_to(0.05);
  EXPECT_EQ(run.totals().force_evals, 4 * 50);
  EXPECT_DOUBLE_EQ(spring_passes(run.totals()), 200.0);
}

TEST(WorkUnits, AnImplicitRunCountsItsNewtonWorkBesideItsEvaluations) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  clothsim::Run run(model, IntegratorKind::ImplicitEuler, 1.0 / 60.0);
  run.advance_to(0.5);
  const RunTotals& t = run.totals();
  EXPECT_GT(t.assemblies, 0);
  EXPECT_LE(t.assemblies, t.newton_iterations) << "a reused matrix is not assembled again";
  EXPECT_LE(t.factored_cg_iterations, t.cg_iterations);
  EXPECT_GT(spring_passes(t), static_cast<double>(t.force_evals) + static_cast<double>(t.cg_iterations))
      << "assemblies and CG iterations each cost at least a pass";
}

TEST(WorkUnits, EveryPieceIsWeightedByItsOwnEntry) {
  RunTotals t;
  t.force_evals = 1;
  t.assemblies = 10;
  t.cg_iterations = 100 + 1000;
  t.factored_cg_iterations = 1000;
  t.factorizations = 10000;
  t.solver_iterations = 1e4;
  t.solver_iteration_passes = 11.0;
  const WorkWeights w{1.0, 2.0, 3.0, 5.0, 7.0};
  EXPECT_DOUBLE_EQ(spring_passes(t, w), 1.0 + 20.0 + 300.0 + 5000.0 + 70000.0 + 1.1e5);
}

// Each solver's step reports its iterations; the run counts them as that solver's, so a
// compare matched on cost sees what a step of N iterations costs (PD's factor, one per step
// size, is weighed as Newton's factor is).
TEST(WorkUnits, AnIterativeSolversRunCountsItsIterationsByItsOwnWeight) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  for (const IntegratorKind kind : {IntegratorKind::Xpbd, IntegratorKind::ProjectiveDynamics, IntegratorKind::Vbd}) {
    clothsim::Run run(model, kind, 1.0 / 60.0);
    run.advance_to(0.5);
    const RunTotals& t = run.totals();
    const WorkWeights& w = work_weights();
    const std::int64_t iterations = 10 * t.steps;  // the solvers' default 10 a step
    const double expected = static_cast<double>(t.force_evals) + w.factorization * static_cast<double>(t.factorizations) +
                            static_cast<double>(iterations) * integrator_info(kind).passes_per_iteration;
    EXPECT_EQ(t.solver_iterations, iterations) << integrator_name(kind);
    EXPECT_DOUBLE_EQ(spring_passes(t), expected) << integrator_name(kind);
  }
}

TEST(WorkUnits, TheCalibratedTableCostsNewtonsPiecesAtLeastAPassEach) {
  const WorkWeights& w = work_weights();
  EXPECT_EQ(w.force_eval, 1.0);
  EXPECT_GE(w.assembly, 1.0);
  EXPECT_GE(w.cg_jacobi, 1.0);
  EXPECT_GT(w.cg_factored, w.cg_jacobi) << "two triangular solves on top of the mat-vec";
  EXPECT_GT(w.factorization, w.cg_factored);
  for (const IntegratorInfo& info : integrator_registry()) {
    if (info.iterations != IterationControl::Solver) continue;
    EXPECT_GE(info.passes_per_iteration, 1.0) << info.name << ": a solver's iteration touches every spring at least once";
  }
}
