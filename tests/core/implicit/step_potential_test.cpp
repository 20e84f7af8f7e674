// The step potential Phi of implicit Euler: its gradient is the residual of the stated
// backward-Euler equation (computed here independently, spring by spring), and it is the
// gradient of Phi (central differences of Phi itself).
#include "core/implicit/step_potential.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"
#include "core/model/state.h"

namespace clothsim::testing {
namespace {

const char* kSheet = R"(
name: sheet
gravity: [0, -9.8, 0]
air_drag: 0.3
cloth:
  particles: [4, 3]
  size: [1, 1]
  particle_mass: 0.2
  springs:
    structural: {stiffness: 900, damping: 3}
    shear:      {stiffness: 500, damping: 2}
    bend:       {stiffness: 100, damping: 1}
  pinned: [[0, 0]]
spheres:
  - {center: [0, -3, 0], radius: 0.5, kinematic: false, mass: 2}
)";

struct StepSetup {
  Model model;
  State start;
  Eigen::Matrix3Xd dv;
  std::vector<double> start_length;
};

StepSetup random_setup(unsigned seed) {
  StepSetup s{model_from_yaml(kSheet), {}, {}, {}};
  s.start = initial_state(s.model);
  std::srand(seed);
  const int B = s.model.num_bodies();
  s.start.x += 0.05 * Eigen::Matrix3Xd::Random(3, B);
  s.start.v = Eigen::Matrix3Xd::Random(3, B);
  s.dv = Eigen::Matrix3Xd::Random(3, B);
  for (int b = 0; b < B; ++b)
    if (s.start.inv_mass[b] == 0.0) s.start.v.col(b).setZero(), s.dv.col(b).setZero();
  step_lengths(s.model, s.start.x, s.start_length);
  return s;
}

TEST(StepPotential, GradientIsTheBackwardEulerResidualWithTheStepDamper) {
  const double h = 0.02;
  for (unsigned seed : {1u, 2u, 3u}) {
    const StepSetup s = random_setup(seed);
    const Model& m = s.model;
    Eigen::Matrix3Xd y, r;
    step_potential(m, s.start, h, s.start_length, s.dv, y, r);
    // The stated equation: r = M dv - h f(y, v), f = -T u per spring + m g - c v.
    const Eigen::Matrix3Xd v = s.start.v + s.dv;
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, m.num_bodies());
    for (std::size_t k = 0; k < m.springs.size(); ++k) {
      const int a = m.springs.a[k], b = m.springs.b[k];
      const Vec3 d = y.col(a) - y.col(b);
      const double l = d.norm(), ln = (s.start.x.col(a) - s.start.x.col(b)).norm();
      const double T = m.springs.ks[k] * (l - m.springs.rest[k]) + m.springs.kd[k] / h * (l - ln);
      f.col(a) -= T * d / l;
      f.col(b) += T * d / l;
    }
    for (int i = 0; i < m.num_bodies(); ++i) {
      if (s.start.inv_mass[i] == 0.0) {
        EXPECT_EQ(r.col(i).norm(), 0.0);
        continue;
      }
      f.col(i) += m.mass[i] * m.gravity;
      if (i < m.num_particles) f.col(i) -= m.air_drag * v.col(i);
      const Vec3 expected = m.mass[i] * s.dv.col(i) - h * f.col(i);
      EXPECT_LT((r.col(i) - expected).norm(), 1e-12 * (1 + expected.norm())) << "body " << i;
    }
    EXPECT_TRUE(y.isApprox(s.start.x + h * v, 1e-15));
  }
}

TEST(StepPotential, GradientIsTheDerivativeOfPhiByFiniteDifferences) {
  const double h = 0.02, eps = 1e-6;
  const StepSetup s = random_setup(5);
  Eigen::Matrix3Xd y, r, scratch;
  step_potential(s.model, s.start, h, s.start_length, s.dv, y, r);
  std::srand(9);
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, s.model.num_bodies());
  for (int b = 0; b < s.model.num_bodies(); ++b)
    if (s.start.inv_mass[b] == 0.0) p.col(b).setZero();
  const double plus = step_potential(s.model, s.start, h, s.start_length, s.dv + eps * p, y, scratch).phi;
  const double minus = step_potential(s.model, s.start, h, s.start_length, s.dv - eps * p, y, scratch).phi;
  const double directional = r.cwiseProduct(p).sum();
  EXPECT_NEAR((plus - minus) / (2 * eps), directional, 1e-6 * (1 + std::abs(directional)));
}

// The implicit family's form (step_form.h): h_e, the dampers' step and the drag's factor apart,
// reference lengths that are not l_n, the barrier and friction at the end point of a stage.
StepForm family_form(const Eigen::Matrix3Xd* lag_x, double theta) {
  StepForm form(0.01, 0.016, 0.01 * 0.01 / 0.016);
  form.lag_x = lag_x;
  form.contact_stage = theta;
  return form;
}

TEST(StepPotential, AFamilyFormsGradientIsItsStatedStageEquation) {
  // r = M dv - h_e f(y, v(y)): the dampers at (l - l_ref) / damper_h, drag at
  // v(y) = (h_e / damper_h) (v_s + dv).
  for (unsigned seed : {1u, 2u}) {
    StepSetup s = random_setup(seed);
    const Model& m = s.model;
    const StepForm form = family_form(nullptr, 1.0);
    for (double& l : s.start_length) l *= 0.97;  // reference lengths of a method's own
    Eigen::Matrix3Xd y, r;
    step_potential(m, s.start, form, s.start_length, s.dv, y, r);
    const Eigen::Matrix3Xd v = (form.h / form.damper_h) * (s.start.v + s.dv);
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, m.num_bodies());
    for (std::size_t k = 0; k < m.springs.size(); ++k) {
      const int a = m.springs.a[k], b = m.springs.b[k];
      const Vec3 d = y.col(a) - y.col(b);
      const double l = d.norm(), l_ref = 0.97 * (s.start.x.col(a) - s.start.x.col(b)).norm();
      const double T = m.springs.ks[k] * (l - m.springs.rest[k]) + m.springs.kd[k] / form.damper_h * (l - l_ref);
      f.col(a) -= T * d / l;
      f.col(b) += T * d / l;
    }
    for (int i = 0; i < m.num_bodies(); ++i) {
      if (s.start.inv_mass[i] == 0.0) continue;
      f.col(i) += m.mass[i] * m.gravity;
      if (i < m.num_particles) f.col(i) -= m.air_drag * v.col(i);
      const Vec3 expected = m.mass[i] * s.dv.col(i) - form.h * f.col(i);
      EXPECT_LT((r.col(i) - expected).norm(), 1e-12 * (1 + expected.norm())) << "body " << i;
    }
  }
}

// The sheet lying 1 cm above the ground, within its barrier (d-hat 2 cm), with friction, moving slowly.
const char* kOnGround = R"(
gravity: [0, -9.8, 0]
air_drag: 0.3
cloth:
  particles: [4, 3]
  size: [1, 1]
  center: [0, 0, 0]
  particle_mass: 0.2
  springs: {structural: {stiffness: 900, damping: 3}, shear: {stiffness: 500, damping: 2}}
  pinned: none
ground: {height: -0.01, friction: 0.4}
collision: {model: barrier, barrier_distance: 0.02, friction_velocity: 0.05}
)";

TEST(StepPotential, AFamilyFormsGradientIsTheDerivativeOfPhiWithTheBarrierAtTheEndPoint) {
  const Model m = model_from_yaml(kOnGround);
  State start = initial_state(m);
  std::srand(3);
  const int B = m.num_bodies();
  start.v = 0.05 * Eigen::Matrix3Xd::Random(3, B);
  Eigen::Matrix3Xd dv = 0.05 * Eigen::Matrix3Xd::Random(3, B);
  const Eigen::Matrix3Xd x_n = start.x;
  State pseudo = start;  // a pseudo-start off x_n, as the family's are
  pseudo.x += 1e-3 * Eigen::Matrix3Xd::Random(3, B);
  std::vector<double> lengths;
  step_lengths(m, start.x, lengths);
  for (const double theta : {1.0, 0.5, 2.0 / 3.0}) {
    const StepForm form = family_form(&x_n, theta);
    Eigen::Matrix3Xd y, r, scratch;
    const PotentialValue at = step_potential(m, pseudo, form, lengths, dv, y, r);
    ASSERT_TRUE(std::isfinite(at.phi));
    {  // the barrier and friction are in it
      Model free = m;
      free.collision.model = ContactModel::Projection;
      Eigen::Matrix3Xd y2, r2;
      step_potential(free, pseudo, form, lengths, dv, y2, r2);
      EXPECT_GT((r - r2).norm(), 1e-3 * r.norm()) << "theta " << theta;
    }
    Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, B);
    const double eps = 1e-7;
    const double plus = step_potential(m, pseudo, form, lengths, dv + eps * p, y, scratch).phi;
    const double minus = step_potential(m, pseudo, form, lengths, dv - eps * p, y, scratch).phi;
    const double directional = r.cwiseProduct(p).sum();
    EXPECT_NEAR((plus - minus) / (2 * eps), directional, 1e-6 * (1 + std::abs(directional))) << "theta " << theta;
  }
}

TEST(StepPotential, SpringLengthsReturnTheLargestStrain) {
  StepSetup s = random_setup(4);
  std::vector<double> length;
  s.start.x = s.model.initial_x;
  s.start.x.col(1) += Vec3(0.1, 0, 0);  // particle 1 sits between 0 and 2 on the first row
  const double strain = spring_lengths(s.model.springs, s.start.x, length);
  ASSERT_EQ(length.size(), s.model.springs.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < length.size(); ++k)
    worst = std::max(worst, length[k] / s.model.springs.rest[k] - 1.0);
  EXPECT_DOUBLE_EQ(strain, worst);
  EXPECT_GT(strain, 0.2);  // the 1/3 m spring from 0 to 1 stretched by 0.1 m
}

}  // namespace
}  // namespace clothsim::testing
