// converge's plan (src/clip/studies/converge_plan.h): the defaults the CLI and the Python module
// share, and the refusals naming the option.
#include "clip/studies/converge_plan.h"

#include <gtest/gtest.h>

#include "clip/common/cli_common.h"

namespace clothsim::clip {
namespace {

TEST(PlanConverge, DefaultsToOneFrameStepFromFiveStatesOfTheFourIterativeMethods) {
  const ConvergenceSpec spec = plan_converge(ConvergeOptions{});
  EXPECT_EQ(spec.h, 1.0 / 60.0) << "\"1/60\" read as the fraction, to the last bit";
  EXPECT_EQ(spec.states, 5);
  EXPECT_EQ(spec.max_iterations, 50);
  EXPECT_EQ(spec.methods, (std::vector<IntegratorKind>{*parse_integrator("xpbd"), *parse_integrator("projective_dynamics"),
                                                       *parse_integrator("vbd"), *parse_integrator("implicit_euler")}));
}

TEST(PlanConverge, TakesTheImplicitFamilyEachAgainstItsOwnStep) {
  ConvergeOptions o;
  o.integrators = "implicit_midpoint,newmark,generalized_alpha,bdf2";
  const ConvergenceSpec spec = plan_converge(o);
  ASSERT_EQ(spec.methods.size(), 4u);
  for (IntegratorKind k : spec.methods) EXPECT_EQ(states_source(k), k) << integrator_name(k);
  EXPECT_EQ(states_source(IntegratorKind::Vbd), kBackwardEuler);
}

TEST(PlanConverge, RefusesAMethodWithoutIterationsAndABadStep) {
  ConvergeOptions o;
  o.integrators = "xpbd,rk4";
  try {
    plan_converge(o);
    FAIL() << "rk4 has no iterations";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--integrators: 'rk4' is not an iterative method"), std::string::npos)
        << e.what();
  }
  o.integrators = "imex";  // one linear solve a half kick: nothing to iterate
  try {
    plan_converge(o);
    FAIL() << "imex has no iterations";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("'imex' is not an iterative method (expected implicit_euler, xpbd, "), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("generalized_alpha or bdf2)"), std::string::npos) << e.what();
  }
  o.integrators = "vbd";
  o.dt = "0";
  EXPECT_THROW(plan_converge(o), UsageError);
  o.dt = "1/120";
  o.states = "0";
  EXPECT_THROW(plan_converge(o), UsageError);
}

}  // namespace
}  // namespace clothsim::clip
