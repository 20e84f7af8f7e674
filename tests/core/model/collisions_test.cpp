// Contact response: the seed's restitution formula on hand-computed cases, inverse-mass
// behaviour (pinned and kinematic bodies), momentum, friction, and no penetration after.
#include "core/model/collisions.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "core/run/simulation.h"

namespace clothsim {
namespace {

using testing::model_from_yaml;

// The seed report's formula in masses, for checking the inverse-mass impulse against it.
double seed_va(double ma, double ua, double mb, double ub, double c) {
  return (ma * ua + mb * ub + mb * c * (ub - ua)) / (ma + mb);
}
double seed_vb(double ma, double ua, double mb, double ub, double c) {
  return (ma * ua + mb * ub + ma * c * (ua - ub)) / (ma + mb);
}

TEST(ContactImpulse, ReproducesTheSeedFormulaForFiniteMasses) {
  struct Case { double ma, ua, mb, ub, c; };
  for (const Case k : {Case{1, -2, 125, 0.5, 0.0}, Case{1, -2, 125, 0.5, 0.8}, Case{3, 1, 2, 4, 0.5},
                       Case{2, -1, 2, 1, 1.0}}) {
    const double j = contact_impulse(k.ua, k.ub, 1 / k.ma, 1 / k.mb, k.c);
    EXPECT_NEAR(k.ua + j / k.ma, seed_va(k.ma, k.ua, k.mb, k.ub, k.c), 1e-12);
    EXPECT_NEAR(k.ub - j / k.mb, seed_vb(k.ma, k.ua, k.mb, k.ub, k.c), 1e-12);
  }
}

TEST(ContactImpulse, InfiniteMassLimitsAreExact) {
  // A particle hitting a kinematic sphere (w_b = 0) moving at 1 m/s: v_a = u_b + C (u_b - u_a).
  const double j = contact_impulse(-3.0, 1.0, 1.0, 0.0, 0.5);
  EXPECT_NEAR(-3.0 + j, 1.0 + 0.5 * (1.0 + 3.0), 1e-12);
  // Both immovable: nothing happens.
  EXPECT_EQ(contact_impulse(-3.0, 1.0, 0.0, 0.0, 0.5), 0.0);
  // Separating bodies are left alone.
  EXPECT_EQ(contact_impulse(2.0, 1.0, 1.0, 1.0, 0.5), 0.0);
}

TEST(FrictionImpulse, RemovesAtMostMuTimesTheNormalImpulseAndNeverReverses) {
  const Vec3 vt(2, 0, 0);
  const Vec3 small = friction_impulse(vt, 1.0, 1.0, 0.0, 0.5);  // cone-limited: 0.5
  EXPECT_NEAR(small.x(), -0.5, 1e-12);
  const Vec3 sticks = friction_impulse(vt, 100.0, 1.0, 0.0, 0.5);  // would reverse: stops instead
  EXPECT_NEAR(vt.x() + sticks.x(), 0.0, 1e-12);
}

const char* kBallUnderCloth = R"(
gravity: [0, 0, 0]
cloth:
  particles: [5, 5]
  size: [1, 1]
  center: [0, 0, 0]
  particle_mass: 1.0
  pinned: none
spheres:
  - {center: [0, -0.45, 0], radius: 0.5, kinematic: false, mass: 10, gravity: false}
collision: {margin: 0.01}
)";

TEST(Collisions, NoParticleIsLeftInsideASphere) {
  const Model m = model_from_yaml(kBallUnderCloth);
  State s = initial_state(m);
  for (int p = 0; p < m.num_particles; ++p) s.v.col(p) = Vec3(0, -1, 0);
  const ContactCounts c = resolve_collisions(m, s);
  EXPECT_GT(c.cloth_sphere, 0);
  const Vec3 centre = s.x.col(m.sphere_body(0));
  for (int p = 0; p < m.num_particles; ++p)
    EXPECT_GE((s.x.col(p) - centre).norm(), 0.5 + 0.01 - 1e-12) << "particle " << p;
}

TEST(Collisions, MomentumIsConservedInADynamicSphereClothExchange) {
  const Model m = model_from_yaml(kBallUnderCloth);
  State s = initial_state(m);
  for (int p = 0; p < m.num_particles; ++p) s.v.col(p) = Vec3(0.2, -1.5, 0.1);
  s.v.col(m.sphere_body(0)) = Vec3(0, 0.5, 0);
  const auto momentum = [&](const State& st) {
    Vec3 p = Vec3::Zero();
    for (int b = 0; b < m.num_bodies(); ++b) p += m.mass[b] * st.v.col(b);
    return p;
  };
  const Vec3 before = momentum(s);
  const ContactCounts c = resolve_collisions(m, s);
  ASSERT_GT(c.cloth_sphere, 0);
  EXPECT_LT((momentum(s) - before).norm(), 1e-12 * (1 + before.norm()));
  EXPECT_LT(s.v(1, m.sphere_body(0)), 0.5);  // the sphere was pushed down by the cloth
}

TEST(Collisions, PinnedParticlesAndKinematicSpheresDoNotMove) {
  const Model m = model_from_yaml(R"(
gravity: [0, 0, 0]
cloth: {particles: [3, 3], size: [1, 1], center: [0, 0, 0], pinned: corners}
spheres: [{center: [0.5, -0.2, 0.5], radius: 0.3, kinematic: true, velocity: [0, 2, 0]}]
)");
  State s = initial_state(m);
  const Vec3 corner = s.x.col(8);  // (2, 2) at (0.5, 0, 0.5) is pinned and inside the sphere
  const Vec3 sphere_v = s.v.col(m.sphere_body(0));
  resolve_collisions(m, s);
  EXPECT_EQ((s.x.col(8) - corner).norm(), 0.0);
  EXPECT_EQ(s.v.col(8).norm(), 0.0);
  EXPECT_EQ((s.v.col(m.sphere_body(0)) - sphere_v).norm(), 0.0);
}

TEST(Collisions, GroundReflectsTheNormalVelocityWithRestitutionAndKeepsTangential) {
  const Model m = model_from_yaml(R"(
gravity: [0, 0, 0]
cloth: {particles: [1, 1], center: [0, -0.05, 0], pinned: none}
ground: {height: 0.0, restitution: 0.5}
)");
  State s = initial_state(m);
  s.v.col(0) = Vec3(1.0, -2.0, 0.5);
  const ContactCounts c = resolve_collisions(m, s);
  EXPECT_EQ(c.cloth_ground, 1);
  EXPECT_NEAR(s.v(1, 0), 1.0, 1e-12);  // -0.5 x -2
  EXPECT_NEAR(s.v(0, 0), 1.0, 1e-12);
  EXPECT_NEAR(s.v(2, 0), 0.5, 1e-12);
  EXPECT_NEAR(s.x(1, 0), 0.01, 1e-12);  // projected to the plane plus margin
}

TEST(Collisions, SpheresBounceOffEachOtherWithTheirRestitution) {
  const Model m = model_from_yaml(R"(
gravity: [0, 0, 0]
cloth: {particles: [1, 1], center: [0, 10, 0], pinned: none}
spheres:
  - {center: [-0.45, 0, 0], radius: 0.5, kinematic: false, mass: 2, velocity: [1, 0, 0]}
  - {center: [0.45, 0, 0], radius: 0.5, kinematic: false, mass: 2, velocity: [-1, 0, 0]}
collision: {sphere_sphere: true, sphere_restitution: 0.8}
)");
  State s = initial_state(m);
  resolve_collisions(m, s);
  EXPECT_NEAR(s.v(0, m.sphere_body(0)), -0.8, 1e-12);
  EXPECT_NEAR(s.v(0, m.sphere_body(1)), 0.8, 1e-12);
  EXPECT_NEAR((s.x.col(m.sphere_body(0)) - s.x.col(m.sphere_body(1))).norm(), 1.0, 1e-12);
}

// A particle held on a collider's plane (the solvers' contacts): its approach reversed times the
// restitution, a separating velocity (a position correction's trace) removed, and friction up
// to mu times the whole normal impulse, the constraint's included.
TEST(HeldContactResponse, RemovesTheCorrectionReversesTheApproachAndBoundsFrictionByTheWholeImpulse) {
  const Vec3 n = Vec3::UnitY();
  const double w = 0.5;  // 2 kg
  // Approaching at 2 m/s, restitution 0.5: leaves at 1 m/s; no friction asked.
  EXPECT_TRUE(held_contact_response(Vec3(0, -2, 0), n, w, 0.5, 0.0, 0.0).isApprox(Vec3(0, 3, 0)));
  // Separating at 1 m/s: removed, whatever the restitution.
  EXPECT_TRUE(held_contact_response(Vec3(0, 1, 0), n, w, 0.9, 0.0, 0.0).isApprox(Vec3(0, -1, 0)));
  // Sliding at 3 m/s, resting (no approach), held by 1 N s, mu 0.5: 0.5 N s of friction on
  // 2 kg takes 0.25 m/s off the slide, never more than the slide.
  const Vec3 dv = held_contact_response(Vec3(3, 0, 0), n, w, 0.0, 0.5, 1.0);
  EXPECT_NEAR(dv.x(), -0.25, 1e-12);
  EXPECT_NEAR(dv.y(), 0.0, 1e-12);
  EXPECT_NEAR(held_contact_response(Vec3(0.1, 0, 0), n, w, 0.0, 0.5, 100.0).x(), -0.1, 1e-12);
  // No held impulse, no approach: nothing for friction to act with.
  EXPECT_TRUE(held_contact_response(Vec3(3, 0, 0), n, w, 0.0, 1.0, 0.0).isZero());
}

}  // namespace
}  // namespace clothsim
