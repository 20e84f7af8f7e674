// Energies, strain and divergence detection on states whose values are known by hand.
#include "core/model/diagnostics.h"

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
  EXPECT_FALSE(check_divergence(m, s).has_value());
  State nan = s;
  nan.x(1, 0) = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(check_bodies(m, nan).has_value());
  EXPECT_NE(check_bodies(m, nan)->reason.find("non-finite position"), std::string::npos);
  State stretched = s;
  stretched.x.col(1) += Vec3(20, 0, 0);  // strain 20 > default bound 10
  ASSERT_TRUE(check_divergence(m, stretched).has_value());
  EXPECT_NE(check_divergence(m, stretched)->reason.find("strain"), std::string::npos);
  EXPECT_FALSE(check_bodies(m, stretched).has_value());  // the body pass reads no springs
  State fast = s;
  fast.v.col(0) = Vec3(1e5, 0, 0);
  ASSERT_TRUE(check_bodies(m, fast).has_value());
  EXPECT_NE(check_bodies(m, fast)->reason.find("kinetic energy"), std::string::npos);
}

TEST(Divergence, NamesTheFirstBodyWithANonFiniteValueAndWhichValue) {
  const Model m = testing::model_from_yaml(kTwo);
  State s = initial_state(m);
  s.x(2, 1) = std::numeric_limits<double>::infinity();
  s.v(0, 1) = std::numeric_limits<double>::quiet_NaN();
  ASSERT_TRUE(check_bodies(m, s).has_value());
  EXPECT_EQ(check_bodies(m, s)->reason, "non-finite position (body 1)");  // position before velocity
  s.x(2, 1) = 0.0;
  EXPECT_EQ(check_bodies(m, s)->reason, "non-finite velocity (body 1)");
  s.v(2, 0) = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(check_bodies(m, s)->reason, "non-finite velocity (body 0)");  // the first body
  // The largest finite values, and subnormal ones, are finite.
  State edge = initial_state(m);
  edge.x(0, 0) = -std::numeric_limits<double>::max();
  edge.x(2, 1) = std::numeric_limits<double>::denorm_min();
  edge.v(0, 1) = -std::numeric_limits<double>::denorm_min();
  EXPECT_FALSE(check_bodies(m, edge).has_value());
}

TEST(Divergence, NonFiniteEnergiesAreDivergenceEvenWithFiniteValues) {
  const Model m = testing::model_from_yaml(kTwo);
  State s = initial_state(m);
  s.v.col(0) = Vec3(1e200, 0, 0);  // finite, but 0.5 m v^2 overflows
  ASSERT_TRUE(check_bodies(m, s).has_value());
  EXPECT_NE(check_bodies(m, s)->reason.find("non-finite kinetic energy"), std::string::npos);
}

TEST(Divergence, AStrainMeasuredElsewhereIsReportedAtItsOwnStepAndTime) {
  const Model m = testing::model_from_yaml(kTwo);
  EXPECT_FALSE(check_strain(m, 9.9, 7, 0.7).has_value());
  const auto bad = check_strain(m, 10.5, 7, 0.7);
  ASSERT_TRUE(bad.has_value());
  EXPECT_EQ(bad->step, 7);
  EXPECT_DOUBLE_EQ(bad->t, 0.7);
  EXPECT_TRUE(check_strain(m, std::numeric_limits<double>::quiet_NaN(), 7, 0.7).has_value());
}

// WRONG's two rules (diagnostics.h), on ledgers and strains written by hand.
TEST(Wrong, EnergyRisingPastTheBoundAboveTheStretchsLowestIsEnergyMade) {
  Model m = testing::model_from_yaml(kTwo);
  m.energy_scale = 10.0 / kWrongEnergyRise;  // bound: 10 J
  EnergyLedger l;
  record_energy(l, 50.0, true);
  record_energy(l, 40.0, false);  // damping took 10 J
  record_energy(l, 49.0, false);  // 9 J back above the lowest: within the bound
  EXPECT_FALSE(check_energy_made(m, l, 3, 0.3));
  record_energy(l, 51.0, false);  // 11 J above the lowest, though only 1 J above the start
  const auto wrong = check_energy_made(m, l, 4, 0.4);
  ASSERT_TRUE(wrong);
  EXPECT_EQ(wrong->step, 4);
  EXPECT_NE(wrong->reason.find("energy rose 11 J with no work done (bound 10 J"), std::string::npos) << wrong->reason;
}

TEST(Wrong, WorkDoneStartsTheStretchAgainAndNonFiniteSamplesAreNoEvidence) {
  Model m = testing::model_from_yaml(kTwo);
  m.energy_scale = 10.0 / kWrongEnergyRise;
  EnergyLedger l;
  record_energy(l, 0.0, true);
  record_energy(l, 500.0, true);  // a sphere pushed the cloth: its energy is the work's
  EXPECT_DOUBLE_EQ(l.rise, 0.0);
  record_energy(l, std::numeric_limits<double>::quiet_NaN(), false);  // divergence's to report
  record_energy(l, std::numeric_limits<double>::infinity(), false);
  EXPECT_DOUBLE_EQ(l.lowest, 500.0);
  EXPECT_FALSE(check_energy_made(m, l, 5, 0.5));
}

TEST(Wrong, AStrainPastTheBoundBeyondTheScenesOwnIsOverStretched) {
  EXPECT_FALSE(check_over_stretched(kWrongStrain - 1e-9, 0.0, 1, 0.1));
  const auto wrong = check_over_stretched(kWrongStrain + 0.01, 0.0, 7, 0.7);
  ASSERT_TRUE(wrong);
  EXPECT_NE(wrong->reason.find("past the bound 1"), std::string::npos) << wrong->reason;
  // Just past it: as many figures as tell the two apart, never "strain 1 past the bound 1".
  EXPECT_EQ(check_over_stretched(kWrongStrain + 0.0012, 0.0, 7, 0.7)->reason, "strain 1.001 past the bound 1");
  EXPECT_EQ(check_over_stretched(kWrongStrain + 1e-5, 0.0, 7, 0.7)->reason, "strain 1.00001 past the bound 1");
  EXPECT_FALSE(check_over_stretched(kWrongStrain + 0.01, 0.1, 7, 0.7)) << "a scene that starts stretched by 0.1";
  EXPECT_FALSE(check_over_stretched(std::numeric_limits<double>::quiet_NaN(), 0.0, 7, 0.7));
}

TEST(Wrong, OnlyAnImmovableBodyThatMovesDoesWork) {
  const Model m = testing::model_from_yaml(kTwo);
  State s = initial_state(m);
  s.v.col(0) = Vec3(3, 0, 0);  // a free particle moving: its own energy, no work
  EXPECT_FALSE(external_work(m, s));
  s.v.col(m.sphere_body(0)) = Vec3(0, 1, 0);  // the kinematic sphere moves
  EXPECT_TRUE(external_work(m, s));
  s.v.col(m.sphere_body(0)).setZero();
  s.inv_mass[1] = 0.0;  // a pinned particle moving (a scripted velocity)
  s.v.col(1) = Vec3(0, 0, 1);
  EXPECT_TRUE(external_work(m, s));
}

}  // namespace
}  // namespace clothsim
