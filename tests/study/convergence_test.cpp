// The convergence study: distances from converged backward Euler per iteration.
#include "study/convergence.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace clothsim
