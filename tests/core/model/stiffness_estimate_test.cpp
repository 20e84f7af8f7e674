// The Gershgorin estimates of the fastest spring frequency and damping rate, against a
// spring whose frequency is known and a cloth whose stiffness matrix is diagonalised here.
#include "core/model/stiffness_estimate.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "test_support.h"
#include "core/integrators/integrator_kind.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

using testing::model_from_yaml;
using testing::scene_path;

// Largest eigenvalue of M^-1 K over the free particles, K the linearised spring stiffness at
// the initial state: sum over springs of ks [P -P; -P P], P = d d^T.
double largest_eigenvalue(const Model& model) {
  std::vector<int> index(model.num_particles, -1);
  int n = 0;
  for (int p = 0; p < model.num_particles; ++p)
    if (model.initial_inv_mass[p] > 0) index[p] = n++;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  const Springs& s = model.springs;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d d = (model.initial_x.col(s.b[i]) - model.initial_x.col(s.a[i])).normalized();
    const Eigen::Matrix3d P = s.ks[i] * d * d.transpose();
    const int a = index[s.a[i]], b = index[s.b[i]];
    if (a >= 0) K.block<3, 3>(3 * a, 3 * a) += P;
    if (b >= 0) K.block<3, 3>(3 * b, 3 * b) += P;
    if (a >= 0 && b >= 0) {
      K.block<3, 3>(3 * a, 3 * b) -= P;
      K.block<3, 3>(3 * b, 3 * a) -= P;
    }
  }
  // Equal masses here, so M^-1 K = K / m stays symmetric.
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues().maxCoeff() /
         model.mass[0];
}

const char* kCloth = R"(
name: small
gravity: [0, 0, 0]
cloth:
  particles: [6, 5]
  size: [1, 1]
  particle_mass: 0.2
  springs:
    structural: {stiffness: 1000, damping: 3}
    shear: {stiffness: 500, damping: 1}
    bend: {stiffness: 200, damping: 0.5}
  pinned: corners
air_drag: 0.1
)";

TEST(StiffnessEstimate, IsExactForASpringTiedToAPin) {
  const StiffnessEstimate e = estimate_stiffness(build_model(load_scene(scene_path("spring.yaml"))));
  EXPECT_DOUBLE_EQ(e.w_max, 10.0);          // sqrt(k / m)
  EXPECT_DOUBLE_EQ(e.c_max, 2.0);           // d / m
  EXPECT_DOUBLE_EQ(e.dt_springs(), 0.2);    // symplectic Euler's limit 2 / w
  EXPECT_DOUBLE_EQ(e.dt_with_damping(), 0.2);
  EXPECT_EQ(e.particle, 1);
}

TEST(StiffnessEstimate, BoundsTheClothsFastestFrequencyFromAboveAndNotLoosely) {
  const Model model = model_from_yaml(kCloth);
  const double w2 = largest_eigenvalue(model);
  const StiffnessEstimate e = estimate_stiffness(model);
  EXPECT_GE(e.w_max * e.w_max, w2 * (1 - 1e-12));
  EXPECT_LE(e.w_max * e.w_max, 3.0 * w2);  // an estimate worth printing, not just a bound
  // Interior row: 4 structural, 4 shear, 4 bend springs, all to free neighbours.
  EXPECT_DOUBLE_EQ(e.w_max * e.w_max, 2.0 * (4 * 1000 + 4 * 500 + 4 * 200) / 0.2);
}

TEST(StiffnessEstimate, DampingRateCountsTheDampersAndAirDrag) {
  const StiffnessEstimate e = estimate_stiffness(model_from_yaml(kCloth));
  EXPECT_DOUBLE_EQ(e.c_max, (2.0 * (4 * 3 + 4 * 1 + 4 * 0.5) + 0.1) / 0.2);
  EXPECT_DOUBLE_EQ(e.dt_with_damping(), 2.0 / std::max(e.w_max, e.c_max));
}

TEST(StiffnessEstimate, WithEveryParticlePinnedThereIsNoLimit) {
  const StiffnessEstimate e =
      estimate_stiffness(build_model(load_scene(scene_path("spring.yaml"), {"cloth.pinned=[[0, 0], [1, 0]]"})));
  EXPECT_EQ(e.particle, -1);
  EXPECT_EQ(e.w_max, 0.0);
  EXPECT_TRUE(std::isinf(e.dt_springs()));
}

StiffnessEstimate mode(double w, double c) {
  StiffnessEstimate e;
  e.w_max = w;
  e.c_max = c;
  return e;
}

TEST(PredictedLimit, UndampedModesHaveTheTextbookLimits) {
  const StiffnessEstimate e = mode(10.0, 0.0);
  EXPECT_EQ(predicted_limit(e, IntegratorKind::ExplicitEuler), 0.0);  // never stable
  EXPECT_EQ(predicted_limit(e, IntegratorKind::Midpoint), 0.0);
  EXPECT_DOUBLE_EQ(predicted_limit(e, IntegratorKind::SymplecticEuler), 2.0 / 10.0);
  EXPECT_NEAR(predicted_limit(e, IntegratorKind::Rk4), std::sqrt(8.0) / 10.0, 1e-6);
  EXPECT_TRUE(std::isinf(predicted_limit(e, IntegratorKind::ImplicitEuler)));
  ImplicitDef course;  // the course's "implicit": one fixed-point iteration, 1 + z + z^2
  course.solver = ImplicitSolver::FixedPoint;
  EXPECT_NEAR(predicted_limit(e, IntegratorKind::ImplicitEuler, course), 1.0 / 10.0, 1e-6);
}

TEST(PredictedLimit, DampersAloneGiveTheRealAxisReach) {
  const StiffnessEstimate e = mode(0.0, 100.0);
  EXPECT_NEAR(predicted_limit(e, IntegratorKind::ExplicitEuler), 2.0 / 100.0, 1e-9);
  EXPECT_NEAR(predicted_limit(e, IntegratorKind::Midpoint), 2.0 / 100.0, 1e-9);
  EXPECT_NEAR(predicted_limit(e, IntegratorKind::Rk4), 2.785293563 / 100.0, 1e-8);
  EXPECT_DOUBLE_EQ(predicted_limit(e, IntegratorKind::SymplecticEuler), 2.0 / 100.0);
}

TEST(PredictedLimit, MatchesTheClosedFormsOfADampedMode) {
  // Underdamped (the damped spring.yaml: w = 10, c = 2): explicit Euler needs
  // |1 + h l|^2 = 1 - h c + h^2 w^2 <= 1, h <= c / w^2; symplectic Euler h^2 w^2 + 2 h c <= 4.
  EXPECT_NEAR(predicted_limit(mode(10.0, 2.0), IntegratorKind::ExplicitEuler), 2.0 / 100.0, 1e-9);
  EXPECT_DOUBLE_EQ(predicted_limit(mode(10.0, 2.0), IntegratorKind::SymplecticEuler), (std::sqrt(404.0) - 2.0) / 100.0);
  // Overdamped (the drape: w ~ 690, c ~ 1.8e4): the fast root l = (-c - sqrt(c^2 - 4 w^2)) / 2.
  const double w = 690.0, c = 1.8e4, fast = 0.5 * (c + std::sqrt(c * c - 4 * w * w));
  EXPECT_NEAR(predicted_limit(mode(w, c), IntegratorKind::ExplicitEuler), 2.0 / fast, 1e-9 * 2.0 / fast);
  EXPECT_NEAR(predicted_limit(mode(w, c), IntegratorKind::Rk4), 2.785293563 / fast, 1e-8 / fast);
  // Without springs or dampers nothing limits the step.
  EXPECT_TRUE(std::isinf(predicted_limit(mode(0.0, 0.0), IntegratorKind::ExplicitEuler)));
}

}  // namespace
}  // namespace clothsim::analysis
