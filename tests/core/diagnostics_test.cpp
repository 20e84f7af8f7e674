// Energies, strain and divergence detection on states whose values are known by hand.
#include "diagnostics.h"

#include <gtest/gtest.h>

#include <limits>

#include "test_support.h"

namespace clothsim {
namespace {

const char* kTwo = R"(
gravity: [0, -10, 0]
cloth:
  particles: [2, 1]
  size: [1, 1]
  center: [0.5, 2, 0]
  particle_mass: 3.0
  springs: {structural: {stiffness: 200, damping: 0}}
  pinned: none
spheres: [{center: [0, -5, 0], radius: 0.1}]
)";

TEST(Energies, AreKineticSpringAndGravityByHand) {
  const Model m = testing::model_from_yaml(kTwo);
  State s = initial_state(m);
  s.v.col(0) = Vec3(1, 0, 0);
  s.v.col(1) = Vec3(0, 2, 0);
  s.x.col(1) += Vec3(0.1, 0, 0);  // stretch by 0.1: 0.5 * 200 * 0.01 = 1 J
  s.v.col(m.sphere_body(0)) = Vec3(5, 0, 0);  // kinematic: not part of the energy
  const Energies e = compute_energies(m, s);
  EXPECT_NEAR(e.kinetic, 0.5 * 3 * 1 + 0.5 * 3 * 4, 1e-12);
  EXPECT_NEAR(e.spring, 1.0, 1e-12);
  EXPECT_NEAR(e.gravity, 2 * 3.0 * 10 * 2.0, 1e-12);  // -m g.x = m 10 y, both at y = 2
  EXPECT_NEAR(e.total(), e.kinetic + e.spring + e.gravity, 1e-12);
}

TEST(MaxStrain, IsTheLargestRelativeExtension) {
  const Model m = testing::model_from_yaml(kTwo);
  State s = initial_state(m);
  s.x.col(1) += Vec3(0.25, 0, 0);
  EXPECT_NEAR(max_strain(m, s), 0.25, 1e-12);
}

TEST(Divergence, IsFoundForNonFiniteValuesExcessiveStrainAndEnergy) {
  const Model m = testing::model_from_yaml(kTwo);
  State s = initial_state(m);
  EXPECT_FALSE(check_divergence(m, s, true).has_value());
  State nan = s;
  nan.x(1, 0) = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(check_divergence(m, nan, false).has_value());
  EXPECT_NE(check_divergence(m, nan, false)->reason.find("non-finite"), std::string::npos);
  State stretched = s;
  stretched.x.col(1) += Vec3(20, 0, 0);  // strain 20 > default bound 10
  ASSERT_TRUE(check_divergence(m, stretched, true).has_value());
  EXPECT_NE(check_divergence(m, stretched, true)->reason.find("strain"), std::string::npos);
  EXPECT_FALSE(check_divergence(m, stretched, false).has_value());  // cheap check: finiteness only
  State fast = s;
  fast.v.col(0) = Vec3(1e5, 0, 0);
  ASSERT_TRUE(check_divergence(m, fast, true).has_value());
  EXPECT_NE(check_divergence(m, fast, true)->reason.find("kinetic energy"), std::string::npos);
}

}  // namespace
}  // namespace clothsim
