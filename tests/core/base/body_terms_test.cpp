// The body terms of a force evaluation (body_terms.h), and the SIMD spring pass that applies
// them as it finishes each particle (spring_kernels.h family_forces_with_body_terms): bit for
// bit the springs summed into a zeroed f followed by body_terms() on every body, on every
// Highway target; and the terms themselves as physics (gravity, drag, 1/m, immovable bodies).
#include "core/base/body_terms.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>

#include "test_support.h"
#include "core/model/forces.h"
#include "core/kernel_test_support.h"
#include "core/springs/spring_kernels.h"

namespace clothsim {
namespace {

using testing::for_each_highway_target;
using testing::model_from_yaml;
using testing::typed_springs;

// A sheet with drag, a ball (a body past the particles), corners pinned by the scene, and
// random positions and velocities near the grid.
struct Case {
  Model model;
  Eigen::Matrix3Xd x, v;
  Eigen::VectorXd inv_mass;
};

Case make_case(int nx, int ny, const std::string& types, double drag, unsigned seed) {
  Case c{model_from_yaml("cloth: {particles: [" + std::to_string(nx) + ", " + std::to_string(ny) +
                         "], size: [2, 1.5], pinned: corners, springs: {" + typed_springs(types) +
                         "}}\nair_drag: " + std::to_string(drag) +
                         "\nspheres: [{center: [0, -2, 0], radius: 0.5}]\n"),
         {}, {}, {}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  c.x = c.model.initial_x;
  c.v.resize(3, c.model.num_bodies());
  for (int b = 0; b < c.model.num_bodies(); ++b)
    for (int k = 0; k < 3; ++k) {
      c.x(k, b) += 0.02 * u(rng);
      c.v(k, b) = u(rng);
    }
  c.inv_mass = c.model.initial_inv_mass;
  return c;
}

BodyTermInputs inputs(const Case& c, bool times_inverse_mass) {
  return body_term_inputs(c.model, c.v, c.inv_mass, times_inverse_mass);
}

// The reference: the springs into a zeroed f, then body_terms() on every body.
Eigen::Matrix3Xd reference(const Case& c, bool times_inverse_mass) {
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, c.model.num_bodies());
  accumulate_spring_forces(c.model, c.x, c.v, f);
  const BodyTermInputs in = inputs(c, times_inverse_mass);
  for (std::size_t i = 0; i < in.bodies; ++i) body_terms(in, i, f.data() + 3 * i);
  return f;
}

bool same_bits(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(BodyTerms, TheFusedPassGivesTheBitsOfTheSpringsThenTheTermsOnEveryTarget) {
  // Sheet widths around every vector length (1, 2, 4, 8 lanes) leave every kind of tail.
  for (const auto& [nx, ny] : {std::pair{5, 4}, std::pair{9, 7}, std::pair{16, 3}, std::pair{25, 25}})
    for (const double drag : {0.0, 0.37})
      for (const bool times_inverse_mass : {false, true}) {
        Case c = make_case(nx, ny, "structural: {}, shear: {}, bend: {}", drag, 7u + nx);
        c.inv_mass[nx + 1] = 0.0;  // one more particle held still (a pin set by an event)
        c.model.gravity_on[nx + 2] = 0;  // and one without gravity, inside a whole vector
        const Eigen::Matrix3Xd expected = reference(c, times_inverse_mass);
        for_each_highway_target([&](const char* target) {
          Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Constant(3, c.model.num_bodies(), 12345.0);  // not zeroed
          std::size_t finished = 0;
          family_forces_with_body_terms(c.model.spring_layout, c.x, c.v, inputs(c, times_inverse_mass), f, finished);
          ASSERT_LE(finished, static_cast<std::size_t>(c.model.num_particles));
          ASSERT_GT(finished, 0u);
          // What the caller does for the rest (forces.cpp): zero, then the terms.
          const BodyTermInputs in = inputs(c, times_inverse_mass);
          f.rightCols(c.model.num_bodies() - static_cast<Eigen::Index>(finished)).setZero();
          for (std::size_t i = finished; i < in.bodies; ++i) body_terms(in, i, f.data() + 3 * i);
          EXPECT_TRUE(same_bits(f, expected))
              << target << ", " << nx << " x " << ny << ", drag " << drag << ", 1/m " << times_inverse_mass
              << ": largest difference " << (f - expected).cwiseAbs().maxCoeff();
        });
      }
}

TEST(BodyTerms, AccelerationsAndTotalForcesAgreeWithTheReferenceBitForBit) {
  const Case c = make_case(12, 10, "structural: {}, shear: {}", 0.2, 3u);
  Eigen::Matrix3Xd a, f;
  accelerations(c.model, c.x, c.v, c.inv_mass, a);
  total_forces(c.model, c.x, c.v, c.inv_mass, f);
  EXPECT_TRUE(same_bits(a, reference(c, true)));
  EXPECT_TRUE(same_bits(f, reference(c, false)));
}

TEST(BodyTerms, GravityDragAndInverseMassAsPhysicsSaysAndImmovableBodiesGetZero) {
  Case c = make_case(3, 3, "", 0.5, 1u);  // no springs: only the body terms
  const BodyTermInputs in = inputs(c, true);
  Eigen::Matrix3Xd a = Eigen::Matrix3Xd::Zero(3, c.model.num_bodies());
  for (std::size_t i = 0; i < in.bodies; ++i) body_terms(in, i, a.data() + 3 * i);
  for (int i = 0; i < c.model.num_bodies(); ++i) {
    if (c.inv_mass[i] == 0.0) {  // pinned corners and the ball
      EXPECT_EQ(a.col(i), Eigen::Vector3d::Zero()) << "body " << i;
      continue;
    }
    // a = g - (c / m) v for a cloth particle.
    const Eigen::Vector3d expected = c.model.gravity - c.model.air_drag * c.inv_mass[i] * c.v.col(i);
    EXPECT_LT((a.col(i) - expected).norm(), 1e-12 * expected.norm()) << "body " << i;
  }
}

}  // namespace
}  // namespace clothsim
