// The Gershgorin estimates of the fastest spring frequency and damping rate, against a
// spring whose frequency is known and a cloth whose stiffness matrix is diagonalised here.
#include "analysis/stiffness_estimate.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "scene_parser.h"
#include "test_support.h"

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

}  // namespace
}  // namespace clothsim::analysis
