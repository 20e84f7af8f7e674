// The integrator registry: one row per integrator drives names, parsing and dispatch.
#include "core/integrators/integrator_kind.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/integrators/integrator.h"
#include "core/model/model.h"

namespace clothsim {
namespace {

TEST(IntegratorRegistry, EveryKindHasOneRowInEnumOrderAndParsesByItsName) {
  const auto& registry = integrator_registry();
  ASSERT_EQ(registry.size(), static_cast<std::size_t>(IntegratorKind::Imex) + 1) << "the last kind";
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < registry.size(); ++i) {
    const IntegratorInfo& info = registry[i];
    EXPECT_EQ(static_cast<std::size_t>(info.kind), i) << info.name;
    EXPECT_TRUE(names.insert(info.name).second) << info.name << " is listed twice";
    EXPECT_EQ(parse_integrator(info.name), info.kind);
    EXPECT_EQ(integrator_name(info.kind), info.name);
    EXPECT_EQ(nominal_force_evals(info.kind), info.nominal_force_evals);
    EXPECT_FALSE(info.description.empty());
  }
  EXPECT_FALSE(parse_integrator("runge_kutta").has_value());
}

TEST(IntegratorRegistry, TheCoursesFixedPointIsNamedAsItselfNotAsBackwardEuler) {
  // Its amplification 1 + z + z^2 is another method's: metrics and tables must tell the two apart.
  ImplicitDef newton, fixed;
  fixed.solver = ImplicitSolver::FixedPoint;
  EXPECT_EQ(method_name(IntegratorKind::ImplicitEuler, newton), "implicit_euler");
  EXPECT_EQ(method_name(IntegratorKind::ImplicitEuler, fixed), "implicit_euler_fixed_point");
  EXPECT_EQ(method_name(IntegratorKind::Rk4, fixed), "rk4") << "the solver key is implicit Euler's alone";
  EXPECT_FALSE(parse_integrator(kFixedPointName).has_value()) << "a lane name, not a registry row";
}

TEST(IntegratorRegistry, TheIterativeSolversAreTheThreeWithIterationBlocks) {
  EXPECT_EQ(parse_integrator("xpbd"), IntegratorKind::Xpbd);
  EXPECT_EQ(parse_integrator("projective_dynamics"), IntegratorKind::ProjectiveDynamics);
  EXPECT_EQ(parse_integrator("vbd"), IntegratorKind::Vbd);
  int iterative = 0;
  for (IntegratorKind k : all_integrators()) iterative += is_iterative_solver(k) ? 1 : 0;
  EXPECT_EQ(iterative, 3);
  EXPECT_FALSE(is_iterative_solver(IntegratorKind::ImplicitEuler));
}

TEST(IntegratorRegistry, TheDefaultComparisonIsTheCoursesFourByName) {
  EXPECT_EQ(default_comparison_list(), "explicit_euler,implicit_euler,midpoint,rk4");
}

// The orders the tests of each method measure (x'' = -w^2 x with damping): 1, 1, 2, 4, 1.
TEST(IntegratorRegistry, EachRowStatesTheOrderItsMethodIsMeasuredAt) {
  EXPECT_EQ(integrator_info(IntegratorKind::ExplicitEuler).order, 1);
  EXPECT_EQ(integrator_info(IntegratorKind::SymplecticEuler).order, 1);
  EXPECT_EQ(integrator_info(IntegratorKind::Midpoint).order, 2);
  EXPECT_EQ(integrator_info(IntegratorKind::Rk4).order, 4);
  EXPECT_EQ(integrator_info(IntegratorKind::ImplicitEuler).order, 1);
}

// `:N` reaches the count its method reads: Newton's cap, or the solver block's sweeps; the
// explicit family has none.
TEST(IntegratorRegistry, IterationCountPointsAtTheFieldItsMethodReads) {
  Model m;
  for (const IntegratorInfo& info : integrator_registry()) {
    int* n = iteration_count(m, info.kind);
    EXPECT_EQ(n == nullptr, info.iterations == IterationControl::None) << info.name;
    if (n) {
      *n = 7;
      EXPECT_EQ(iteration_count(static_cast<const Model&>(m), info.kind), 7) << info.name;
    }
  }
  EXPECT_EQ(m.implicit.newton_max_iterations, 7);
  EXPECT_EQ(m.solvers.xpbd.iterations, 7);
  EXPECT_EQ(m.solvers.projective_dynamics.iterations, 7);
  EXPECT_EQ(m.solvers.vbd.iterations, 7);
  m.implicit.newton_max_iterations = 1;
  EXPECT_EQ(m.implicit.newton_mode(), NewtonMode::BaraffWitkin);
  m.implicit.newton_max_iterations = 2;
  EXPECT_EQ(m.implicit.newton_mode(), NewtonMode::Converged);
}

// The rows' limits are the linear theory of DESIGN's table on the undamped oscillator.
TEST(IntegratorRegistry, PredictedLimitsAreEachRowsStabilityRegion) {
  analysis::StiffnessEstimate e;
  e.w_max = 10.0;
  EXPECT_EQ(analysis::predicted_limit(e, IntegratorKind::ExplicitEuler), 0.0);
  EXPECT_DOUBLE_EQ(analysis::predicted_limit(e, IntegratorKind::SymplecticEuler), 0.2);
  EXPECT_NEAR(analysis::predicted_limit(e, IntegratorKind::Rk4), std::sqrt(8.0) / 10.0, 1e-6);
  EXPECT_TRUE(std::isinf(analysis::predicted_limit(e, IntegratorKind::ImplicitEuler)));
  ImplicitDef fixed_point;
  fixed_point.solver = ImplicitSolver::FixedPoint;
  EXPECT_NEAR(analysis::predicted_limit(e, IntegratorKind::ImplicitEuler, fixed_point), 0.1, 1e-6);  // w h <= 1
  for (const IntegratorInfo& info : integrator_registry()) {
    if (info.iterations == IterationControl::Solver) {
      EXPECT_TRUE(std::isinf(analysis::predicted_limit(e, info.kind))) << info.name;
    }
  }
}

// Rows with solver iterations weigh them; the course's four are the comparison's slots.
TEST(IntegratorRegistry, SolverRowsWeighTheirIterationsAndTheCourseIsTheComparisonSlots) {
  for (const IntegratorInfo& info : integrator_registry())
    EXPECT_EQ(info.passes_per_iteration > 0.0, info.iterations == IterationControl::Solver) << info.name;
  const std::vector<IntegratorKind> four = comparison_integrators();
  ASSERT_EQ(four.size(), 4u);
  EXPECT_EQ(four[1], kBackwardEuler);
}

}  // namespace
}  // namespace clothsim
