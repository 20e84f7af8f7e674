// The system force pass: gravity, drag, filtering of immovable bodies, Newton's third law.
#include "core/model/forces.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "core/model/state.h"

namespace clothsim {
namespace {

using testing::model_from_yaml;

const char* kSheet = R"(
gravity: [0, -9.8, 0]
air_drag: 0.5
cloth:
  particles: [4, 3]
  size: [1, 1]
  particle_mass: 2.0
  springs:
    structural: {stiffness: 100, damping: 1}
    shear: {stiffness: 50, damping: 1}
  pinned: [[0, 0]]
spheres:
  - {center: [0, 3, 0], radius: 0.2, kinematic: false, mass: 5}
  - {center: [0, 5, 0], radius: 0.2}
)";

TEST(Forces, GravityActsAsMassTimesGOnMovableBodiesOnly) {
  const Model m = model_from_yaml(kSheet);
  const State s = initial_state(m);
  Eigen::Matrix3Xd f;
  total_forces(m, s.x, Eigen::Matrix3Xd::Zero(3, m.num_bodies()), s.inv_mass, f);
  // Unstretched springs, no velocity: gravity alone.
  EXPECT_NEAR(f(1, 5), -2.0 * 9.8, 1e-9);                  // a free particle
  EXPECT_EQ(f.col(0).norm(), 0.0);                         // the pinned particle
  EXPECT_NEAR(f(1, m.sphere_body(0)), -5.0 * 9.8, 1e-9);   // the dynamic sphere
  EXPECT_EQ(f.col(m.sphere_body(1)).norm(), 0.0);          // the kinematic sphere
}

TEST(Forces, DragOpposesVelocityOnClothButNotOnSpheres) {
  const Model m = model_from_yaml(kSheet, {"gravity=[0,0,0]"});
  State s = initial_state(m);
  s.v.setZero();
  s.v.col(5) = Vec3(0, 0, 2);              // every particle moves together would stretch nothing;
  s.v.col(m.sphere_body(0)) = Vec3(1, 0, 0);
  Eigen::Matrix3Xd with_drag, without;
  total_forces(m, s.x, s.v, s.inv_mass, with_drag);
  const Model no_drag = model_from_yaml(kSheet, {"gravity=[0,0,0]", "air_drag=0"});
  total_forces(no_drag, s.x, s.v, s.inv_mass, without);
  EXPECT_NEAR((with_drag.col(5) - without.col(5) - Vec3(0, 0, -0.5 * 2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((with_drag.col(m.sphere_body(0)) - without.col(m.sphere_body(0))).norm(), 0.0, 1e-12);
}

TEST(Forces, SpringForcesSumToZeroSoMomentumIsConserved) {
  const Model m = model_from_yaml(kSheet, {"gravity=[0,0,0]", "air_drag=0", "cloth.pinned=none"});
  State s = initial_state(m);
  s.x.col(3) += Vec3(0.2, -0.1, 0.3);  // stretch a few springs
  s.v.col(7) = Vec3(1, 2, 3);
  Eigen::Matrix3Xd f;
  total_forces(m, s.x, s.v, s.inv_mass, f);
  EXPECT_GT(f.norm(), 1.0);
  EXPECT_LT(f.rowwise().sum().norm(), 1e-9);
}

TEST(Forces, AccelerationIsForceOverMassAndZeroWhereImmovable) {
  const Model m = model_from_yaml(kSheet);
  State s = initial_state(m);
  s.x.col(6) += Vec3(0.1, 0.0, 0.05);
  Eigen::Matrix3Xd f, a;
  total_forces(m, s.x, s.v, s.inv_mass, f);
  accelerations(m, s.x, s.v, s.inv_mass, a);
  for (int b = 0; b < m.num_bodies(); ++b)
    EXPECT_NEAR((a.col(b) - f.col(b) * s.inv_mass[b]).norm(), 0.0, 1e-12) << "body " << b;
  EXPECT_EQ(a.col(0).norm(), 0.0);
}

}  // namespace
}  // namespace clothsim
