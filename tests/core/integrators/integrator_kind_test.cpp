// The integrator registry: one row per integrator drives names, parsing and dispatch.
#include "core/integrators/integrator_kind.h"

#include <gtest/gtest.h>

#include <set>

#include "core/integrators/integrator.h"

namespace clothsim {
namespace {

TEST(IntegratorRegistry, EveryKindHasOneRowInEnumOrderAndParsesByItsName) {
  const auto& registry = integrator_registry();
  ASSERT_EQ(registry.size(), 8u);
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

}  // namespace
}  // namespace clothsim
