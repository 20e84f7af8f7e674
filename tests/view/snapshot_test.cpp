// The snapshot the renderer draws: geometry of the state, and no words (the overlay lines and
// banners are the tools' to write: src/clip/frames/overlay_text.h, tests/clip/frames/overlay_text_test.cpp).
#include "view/snapshot.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim {
namespace {

TEST(Snapshot, CarriesTheStatesGeometryWithUnitNormalsAndNoText) {
  const Model model = build_model(parse_scene(R"(
cloth: {particles: [3, 2], size: [2, 1], plane: xz, center: [0, 1, 0], springs: {structural: {}}}
spheres: [{center: [0, 0, 0], radius: 0.5, kinematic: true}]
)", "snapshot"));
  State state = initial_state(model);
  state.x(1, 4) += 0.25;  // one particle lifted: its faces tilt, its normal stays unit
  const RenderFrame f = make_render_frame(model, state, RenderDef{});
  ASSERT_EQ(f.cloth_positions.size(), 3u * 6);
  EXPECT_FLOAT_EQ(f.cloth_positions[3 * 4 + 1], static_cast<float>(state.x(1, 4)));
  ASSERT_EQ(f.cloth_normals.size(), 3u * 6);
  for (int p = 0; p < 6; ++p)
    EXPECT_NEAR(std::hypot(f.cloth_normals[3 * p], f.cloth_normals[3 * p + 1], f.cloth_normals[3 * p + 2]), 1.0, 1e-6);
  EXPECT_EQ(f.cloth_triangles, model.triangles);
  ASSERT_EQ(f.spheres.size(), 1u);
  EXPECT_FLOAT_EQ(f.spheres[0].radius, 0.5f);
  EXPECT_TRUE(f.overlay_lines.empty()) << "the words are the tools'";
  EXPECT_TRUE(f.banner.empty());
}

TEST(Snapshot, DrawsTheSpringsOfAClothWithoutTriangles) {
  const Model chain = build_model(parse_scene("cloth: {particles: [4, 1], springs: {structural: {}}}\n", "chain"));
  const RenderFrame f = make_render_frame(chain, initial_state(chain), RenderDef{});
  EXPECT_TRUE(f.cloth_triangles.empty());
  EXPECT_EQ(f.spring_lines.size(), 2u * 3) << "three springs, two ends each";
  EXPECT_TRUE(f.draw_particles);
}

TEST(Snapshot, TakesTheSceneCameraSizeAndSpringLinesFromTheRenderSettings) {
  const SceneDef scene = parse_scene(R"(
cloth: {particles: [3, 3], springs: {structural: {}}}
render: {width: 320, height: 200, camera: {eye: [1, 2, 3], target: [0, 1, 0], fov: 30}, draw_springs: true}
)", "look");
  const Model model = build_model(scene);
  const RenderFrame f = make_render_frame(model, initial_state(model), scene.render);
  EXPECT_EQ(f.width, 320);
  EXPECT_EQ(f.height, 200);
  EXPECT_FLOAT_EQ(f.camera.eye[2], 3.f);
  EXPECT_FLOAT_EQ(f.camera.fov_deg, 30.f);
  EXPECT_EQ(f.spring_lines.size(), 2u * model.springs.size()) << "render.draw_springs draws every spring";
}

}  // namespace
}  // namespace clothsim
