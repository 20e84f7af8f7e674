// Per-particle colouring fields: strain averaged to particles, speed, distance.
#include "view/vertex_fields.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace clothsim;

namespace {

// Three particles in a row, structural springs only, 0.5 m apart at rest.
const char* kRow = R"(
name: row
cloth: {particles: [3, 1], size: [1, 0.5], springs: {structural: {stiffness: 100}}}
)";

}  // namespace

TEST(VertexFields, StrainIsTheMeanOfTheSpringsEndingAtEachParticle) {
  const Model model = clothsim::testing::model_from_yaml(kRow);
  ASSERT_EQ(model.num_particles, 3);
  ASSERT_EQ(model.springs.size(), 2u);
  State state = initial_state(model);
  // Stretch the second spring by 10 %: particle 2 moves 0.05 m away along the row.
  const Eigen::Vector3d along = (state.x.col(2) - state.x.col(1)).normalized();
  state.x.col(2) += 0.05 * along;
  const std::vector<float> s = vertex_strain(model, state);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_NEAR(s[0], 0.0, 1e-7);
  EXPECT_NEAR(s[1], 0.05, 1e-6) << "(0 + 0.1) / 2";
  EXPECT_NEAR(s[2], 0.1, 1e-6);
  // Compression counts as strain too: |l/l0 - 1|.
  state.x.col(2) -= 0.1 * along;
  EXPECT_NEAR(vertex_strain(model, state)[2], 0.1, 1e-6);
}

TEST(VertexFields, SpeedAndDistance) {
  const Model model = clothsim::testing::model_from_yaml(kRow);
  State state = initial_state(model);
  state.v.col(1) = Eigen::Vector3d(3, 0, 4);
  const std::vector<float> v = vertex_speed(model, state);
  EXPECT_FLOAT_EQ(v[1], 5.f);
  EXPECT_FLOAT_EQ(v[0], 0.f);
  const std::vector<double> a{0, 0, 0, 1, 1, 1}, b{0, 0, 1e-9, 1, 4, 5};
  const std::vector<float> d = vertex_distance(a, b);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_NEAR(d[0], 1e-9, 1e-15) << "resolved in double";
  EXPECT_FLOAT_EQ(d[1], 5.f);
}

TEST(VertexFields, NamesParseBothWays) {
  for (FieldKind k : {FieldKind::None, FieldKind::Error, FieldKind::Strain, FieldKind::Speed})
    EXPECT_EQ(parse_field_kind(field_kind_name(k)), k);
  EXPECT_FALSE(parse_field_kind("rainbow"));
  EXPECT_EQ(field_label(FieldKind::Error), "error [m]");
}
