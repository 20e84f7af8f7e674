// The contacts implicit Euler holds inside its solve: which particles are predicted, where
// their planes lie, that a held particle lies on its plane, and which are let go.
#include "core/implicit/step_contacts.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "core/model/state.h"

namespace clothsim::testing {
namespace {

// Two particles over a kinematic ball moving up at 1 m/s, and a ground.
const char* kScene = R"(
name: contacts
gravity: [0, -9.8, 0]
cloth:
  particles: [2, 1]
  size: [3, 1]
  center: [0, 1.015, 0]
  particle_mass: 0.5
  springs: {structural: {stiffness: 100, damping: 0}}
  pinned: none
spheres:
  - {center: [-1.5, 0, 0], radius: 1.0, kinematic: true, restitution: 0.5,
     motion: [{t: 0, velocity: [0, 1, 0]}]}
ground: {height: 0.95, restitution: 0.0}
collision: {margin: 0.01}
)";

TEST(StepContacts, PredictsTheParticlesThatWouldEndInsideAColliderWithItsEndOfStepPlane) {
  const Model m = model_from_yaml(kScene);
  State s = initial_state(m);
  s.v.col(1) = Vec3(0, -10, 0);  // particle 1 heads for the ground; particle 0 sits over the ball
  const double h = 0.01;
  StepContacts contacts;
  predict_step_contacts(m, s, h, nullptr, contacts);
  ASSERT_EQ(contacts.size(), 2u);
  // Particle 0 (at y = 1.015 over the ball's top at 1.0): the ball rises 1 cm in the step, so
  // it would end 0.5 cm inside the reach 1.01. Its plane is the ball's at the end of the step.
  EXPECT_EQ(contacts.filter.body[0], 0);
  EXPECT_EQ(contacts.collider[0], 0);
  EXPECT_TRUE(contacts.filter.normal[0].isApprox(Vec3::UnitY()));
  EXPECT_NEAR(contacts.plane[0], 0.01 + 1.0 + 0.01, 1e-8);
  // Particle 1 falls 10 cm: through the ground's margin (0.95 + 0.01).
  EXPECT_EQ(contacts.filter.body[1], 1);
  EXPECT_EQ(contacts.collider[1], -1);
  EXPECT_NEAR(contacts.plane[1], 0.96, 1e-8);
}

// The scene's first step of h = 0.01 s with particle 1 falling at 10 m/s: its predicted
// contacts, and the end positions with the held particles placed on their planes.
struct FirstStep {
  Model model = model_from_yaml(kScene);
  State start = initial_state(model);
  double h = 0.01;
  StepContacts contacts;
  Eigen::Matrix3Xd y;
  FirstStep() {
    start.v.col(1) = Vec3(0, -10, 0);
    predict_step_contacts(model, start, h, nullptr, contacts);
    Eigen::Matrix3Xd dv = Eigen::Matrix3Xd::Zero(3, model.num_bodies());
    place_on_planes(contacts, start, h, dv);
    y = start.x + h * (start.v + dv);
  }
};

TEST(StepContacts, HeldParticlesArePlacedOnTheirPlanesJustBeyondTheDetectionDistance) {
  const FirstStep f;
  const Model& m = f.model;
  const State& s = f.start;
  const double h = f.h;
  const Eigen::Matrix3Xd& y = f.y;
  const Vec3 centre = s.x.col(m.sphere_body(0)) + h * s.v.col(m.sphere_body(0));
  EXPECT_NEAR((y.col(0) - centre).norm(), 1.01 + kContactClearance, 1e-12);
  EXPECT_NEAR(y(1, 1), 0.96 + kContactClearance, 1e-12);
}

TEST(StepContacts, LetsGoOfPullingContactsOnceAndTakesInPenetratingOnes) {
  FirstStep f;
  const Model& m = f.model;
  const State& s = f.start;
  const double h = f.h;
  const Eigen::Matrix3Xd& y = f.y;
  StepContacts& contacts = f.contacts;
  ASSERT_EQ(contacts.size(), 2u);
  // Impulses: particle 0 pulled towards the ball (r . n < 0), particle 1 pushed out.
  Eigen::Matrix3Xd r = Eigen::Matrix3Xd::Zero(3, m.num_bodies());
  r.col(0) = Vec3(0, -1, 0);
  r.col(1) = Vec3(0, 2, 0);
  EXPECT_TRUE(update_step_contacts(m, s, h, y, r, contacts));
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts.filter.body[0], 1);
  // Let go each time it pulls, three times a step at most: taken in again (it ends inside the
  // ball) after its third release, it stays held, so the rounds end.
  Eigen::Matrix3Xd inside = y;
  inside(1, 0) = 1.0;
  for (int release = 2; release <= 3; ++release) {
    EXPECT_TRUE(take_in_step_contacts(m, s, h, inside, contacts));
    ASSERT_EQ(contacts.size(), 2u);
    EXPECT_TRUE(let_go_step_contacts(r, contacts)) << "release " << release;
    ASSERT_EQ(contacts.size(), 1u);
  }
  EXPECT_TRUE(take_in_step_contacts(m, s, h, inside, contacts));
  EXPECT_FALSE(update_step_contacts(m, s, h, inside, r, contacts));
  EXPECT_EQ(contacts.size(), 2u);
}

// Particle 0 held on the rising ball (the only contact predicted from rest), given the end
// velocity v, then the response: its velocity after it.
Vec3 responded(const Vec3& v) {
  const Model m = model_from_yaml(kScene);
  State s = initial_state(m);
  StepContacts contacts;
  predict_step_contacts(m, s, 0.01, nullptr, contacts);
  EXPECT_EQ(contacts.size(), 1u);
  EXPECT_EQ(contacts.filter.body[0], 0);
  s.v.col(0) = v;
  respond_to_step_contacts(m, contacts, Eigen::Matrix3Xd::Zero(3, m.num_bodies()), s);
  return s.v.col(0);
}

TEST(StepContacts, TheResponseIsTheSeedsRestitutionRelativeToTheMovingBall) {
  // Approaching the ball (which rises at 1 m/s) at 3 m/s: relative normal velocity -3 -> +1.5
  // (C_R = 0.5), so 1 + 1.5 absolute; tangential kept.
  const Vec3 v = responded(Vec3(0.2, -2.0, 0));
  EXPECT_NEAR(v.y(), 2.5, 1e-12);
  EXPECT_NEAR(v.x(), 0.2, 1e-12);
}

TEST(StepContacts, AHeldParticleKeepsNoSeparatingVelocityFromBeingMovedOutOfAPenetration) {
  // Moved 1 cm out of the ball in a 25 us step, a held particle would carry 400 m/s away
  // from it: the response removes that, leaving it at the ball's normal velocity.
  const Vec3 v = responded(Vec3(0.2, 400.0, 0));
  EXPECT_NEAR(v.y(), 1.0, 1e-12);  // the ball rises at 1 m/s
  EXPECT_NEAR(v.x(), 0.2, 1e-12);
}

}  // namespace
}  // namespace clothsim::testing
