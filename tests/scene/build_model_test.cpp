// The grid builder: spring counts per type and shape, rest lengths, pinning, bodies, timeline.
#include "core/model/model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"

namespace clothsim {
namespace {

using testing::model_from_yaml;

int count(const Model& m, SpringType t) {
  int n = 0;
  for (SpringType s : m.springs.type) n += s == t;
  return n;
}

TEST(Model, SheetHasTheSeedsSpringCounts) {
  const Model m = model_from_yaml(R"(
cloth:
  particles: [5, 4]
  springs: {structural: {}, shear: {}, bend: {}}
)");
  EXPECT_EQ(m.num_particles, 20);
  EXPECT_EQ(count(m, SpringType::Structural), 4 * 4 + 5 * 3);  // rows + columns
  EXPECT_EQ(count(m, SpringType::Shear), 2 * 4 * 3);           // two diagonals per cell
  EXPECT_EQ(count(m, SpringType::Bend), 3 * 4 + 5 * 2);        // two apart along each axis
  EXPECT_EQ(m.triangles.size(), 3u * 2 * 4 * 3);
}

TEST(Model, OnlyDeclaredSpringTypesAreBuilt) {
  const Model m = model_from_yaml("cloth: {particles: [6, 6], springs: {shear: {stiffness: 5}}}");
  EXPECT_EQ(count(m, SpringType::Structural), 0);
  EXPECT_EQ(count(m, SpringType::Bend), 0);
  EXPECT_EQ(count(m, SpringType::Shear), 50);
  const Model none = model_from_yaml("cloth: {particles: [6, 6]}");
  EXPECT_EQ(none.springs.size(), 0u);
}

TEST(Model, SingleSpringAndChain) {
  const Model spring = model_from_yaml(R"(
cloth: {particles: [2, 1], size: [1.5, 1], springs: {structural: {}, shear: {}, bend: {}}, pinned: [[0, 0]]}
)");
  ASSERT_EQ(spring.springs.size(), 1u);
  EXPECT_NEAR(spring.springs.rest[0], 1.5, 1e-12);
  EXPECT_TRUE(spring.triangles.empty());
  const Model chain = model_from_yaml("cloth: {particles: [10, 1], springs: {structural: {}, bend: {}}}");
  EXPECT_EQ(count(chain, SpringType::Structural), 9);
  EXPECT_EQ(count(chain, SpringType::Bend), 8);
}

TEST(Model, RestLengthsAreTheGridSpacingAndStretchIsApplied) {
  const Model m = model_from_yaml(R"(
cloth: {particles: [3, 3], size: [2, 2], plane: xy, center: [0, 1, 0], springs: {structural: {}, shear: {}},
        initial_stretch: 0.25}
)");
  for (std::size_t s = 0; s < m.springs.size(); ++s) {
    const double expected = m.springs.type[s] == SpringType::Shear ? std::sqrt(2.0) : 1.0;
    EXPECT_NEAR(m.springs.rest[s], expected, 1e-12);
  }
  // xy hangs with row j = 0 on top; particle (2, 0) moved 0.25 m along x.
  EXPECT_NEAR(m.initial_x(1, 0), 2.0, 1e-12);
  EXPECT_NEAR(m.initial_x(1, 6), 0.0, 1e-12);
  EXPECT_NEAR(m.initial_x(0, 2), 1.25, 1e-12);
}

// The particles a model starts pinned (inverse mass 0), in index order.
std::vector<int> pinned_particles(const Model& m) {
  std::vector<int> out;
  for (int p = 0; p < m.num_particles; ++p)
    if (m.initial_inv_mass[p] == 0.0) out.push_back(p);
  return out;
}

TEST(Model, PinModesFreezeTheRightParticles) {
  const auto pinned = pinned_particles;
  EXPECT_EQ(pinned(model_from_yaml("cloth: {particles: [4, 3], pinned: corners}")), (std::vector<int>{0, 3, 8, 11}));
  EXPECT_EQ(pinned(model_from_yaml("cloth: {particles: [4, 3], pinned: top_edge}")), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(pinned(model_from_yaml("cloth: {particles: [4, 3], pinned: none}")), (std::vector<int>{}));
  EXPECT_EQ(pinned(model_from_yaml("cloth: {particles: [4, 3], pinned: [[1, 2], [3, 0]]}")), (std::vector<int>{3, 9}));
}

// Particle (i, j) is j * nx + i; on this 4 x 3 grid:
//    0  1  2  3     row j = 0: top_edge
//    4  5  6  7
//    8  9 10 11     row j = 2: bottom_edge; column i = 0: left_edge, i = 3: right_edge
std::vector<int> pinned_on_4x3(const std::string& spec) {
  return pinned_particles(model_from_yaml("cloth: {particles: [4, 3], pinned: " + spec + "}"));
}

TEST(Model, EdgePinsFreezeTheirRowOrColumn) {
  const auto pinned = pinned_on_4x3;
  EXPECT_EQ(pinned("top_edge"), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(pinned("bottom_edge"), (std::vector<int>{8, 9, 10, 11}));
  EXPECT_EQ(pinned("left_edge"), (std::vector<int>{0, 4, 8}));
  EXPECT_EQ(pinned("right_edge"), (std::vector<int>{3, 7, 11}));
  // A list of edges is their union, each particle once; forms mix.
  EXPECT_EQ(pinned("[left_edge, top_edge]"), (std::vector<int>{0, 1, 2, 3, 4, 8}));
  EXPECT_EQ(pinned("[right_edge, corners, [1, 1]]"), (std::vector<int>{0, 3, 5, 7, 8, 11}));
}

TEST(Model, RangePinsFreezeTheirColumnsAndRows) {
  const auto pinned = pinned_on_4x3;
  EXPECT_EQ(pinned("{i: [1, 2], j: [0, 1]}"), (std::vector<int>{1, 2, 5, 6}));
  EXPECT_EQ(pinned("{i: 0}"), pinned("left_edge"));          // an axis left out: all of it
  EXPECT_EQ(pinned("{j: [2, 2]}"), pinned("bottom_edge"));
  EXPECT_EQ(pinned("[{i: 3, j: [0, 1]}, [0, 2]]"), (std::vector<int>{3, 7, 8}));
}

TEST(Model, EdgesFollowTheGridWhenSetChangesItsSize) {
  const Model m = model_from_yaml("cloth: {particles: [4, 3], pinned: right_edge}", {"cloth.particles=[6,2]"});
  EXPECT_EQ(m.initial_inv_mass[5], 0.0);
  EXPECT_EQ(m.initial_inv_mass[11], 0.0);
  EXPECT_EQ(m.initial_inv_mass[3], 1.0);
}

TEST(Model, EventsTakeTheSameSelectionsAsPinned) {
  const Model m = model_from_yaml("cloth: {particles: [4, 3], pinned: none}\n"
                                  "events: [{t: 1, pin: left_edge}, {t: 2, unpin: [{i: [2, 3], j: 0}]}]\n");
  ASSERT_EQ(m.timeline.size(), 5u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(m.timeline[k].kind, TimedAction::Kind::Pin);
    EXPECT_EQ(m.timeline[k].body, std::vector<int>({0, 4, 8})[k]);
  }
  EXPECT_EQ(m.timeline[3].body, 2);
  EXPECT_EQ(m.timeline[4].body, 3);
  EXPECT_EQ(m.timeline[4].kind, TimedAction::Kind::Unpin);
}

TEST(Model, SelectedParticlesCountsEachOnce) {
  using K = GridSelection::Kind;
  EXPECT_EQ(selected_particles({{K::Corners}}, 1, 1), (std::vector<int>{0}));
  EXPECT_EQ(selected_particles({{K::TopEdge}, {K::Range, 0, 1, 0, 0}}, 3, 2), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(selected_particles({}, 3, 2), (std::vector<int>{}));
}

TEST(Model, SpheresAreBodiesAfterTheParticles) {
  const Model m = model_from_yaml(R"(
cloth: {particles: [2, 2]}
spheres:
  - {center: [1, 2, 3], radius: 0.5}
  - {center: [0, 5, 0], radius: 0.3, kinematic: false, mass: 4, gravity: false}
)");
  ASSERT_EQ(m.num_bodies(), 6);
  EXPECT_EQ(m.initial_inv_mass[4], 0.0);           // kinematic
  EXPECT_TRUE(std::isinf(m.mass[4]));
  EXPECT_NEAR(m.initial_inv_mass[5], 0.25, 1e-15);  // dynamic
  EXPECT_EQ(m.gravity_on[5], 0);
  EXPECT_EQ(m.initial_x.col(4), Vec3(1, 2, 3));
}

TEST(Model, TimelineIsSortedByTime) {
  const Model m = model_from_yaml(R"(
cloth: {particles: [2, 2]}
spheres: [{radius: 0.1, motion: [{t: 1, velocity: [1, 0, 0]}, {t: 2, velocity: [0, 0, 1]}]}]
events: [{t: 1.5, unpin: [[0, 0]]}, {t: 0.5, pin: [[1, 1]]}]
)");
  ASSERT_EQ(m.timeline.size(), 4u);
  for (std::size_t i = 1; i < m.timeline.size(); ++i) EXPECT_LE(m.timeline[i - 1].t, m.timeline[i].t);
  EXPECT_EQ(m.timeline[0].kind, TimedAction::Kind::Pin);
  EXPECT_EQ(m.timeline[2].kind, TimedAction::Kind::Unpin);
}

}  // namespace
}  // namespace clothsim
