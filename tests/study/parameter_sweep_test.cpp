// Sweeping a scene key: one validated scene per value, and clear errors for a key that is
// not there or not a number.
#include "study/parameter_sweep.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

using testing::scene_path;

TEST(ParameterSweep, AppliesEachValueAfterTheUsersOwnSets) {
  const auto scenes = sweep_scenes(scene_path("spring.yaml"),
                                   {"cloth.springs.structural.stiffness=7", "cloth.particle_mass=2"},
                                   "cloth.springs.structural.stiffness", {50.0, 200.0});
  ASSERT_EQ(scenes.size(), 2u);
  EXPECT_EQ(scenes[0].value, 50.0);
  EXPECT_EQ(scenes[0].scene.cloth.structural->stiffness, 50.0);  // the sweep wins over the --set
  EXPECT_EQ(scenes[1].scene.cloth.structural->stiffness, 200.0);
  EXPECT_EQ(scenes[1].scene.cloth.particle_mass, 2.0);           // other sets still apply
}

TEST(ParameterSweep, KeyThatTakesTextIsNotANumberToSweep) {
  try {
    sweep_scenes(scene_path("spring.yaml"), {}, "name", {1.0, 2.0});
    FAIL() << "name accepts any text";
  } catch (const StudyError& e) {
    EXPECT_NE(std::string(e.what()).find("name is not a numeric scene key"), std::string::npos) << e.what();
  }
}

TEST(ParameterSweep, KeyTheSceneGivesAsAWordIsNotANumberToSweep) {
  try {
    sweep_scenes(scene_path("spring.yaml"), {}, "cloth.plane", {1.0});
    FAIL() << "cloth.plane is xz or xy";
  } catch (const StudyError& e) {
    EXPECT_NE(std::string(e.what()).find("cloth.plane is not a numeric scene key (the scene gives it 'xz')"),
              std::string::npos)
        << e.what();
  }
}

TEST(ParameterSweep, KeyThatDoesNotExistIsTheParsersErrorNamingIt) {
  try {
    sweep_scenes(scene_path("spring.yaml"), {}, "cloth.springs.structural.stifness", {1.0});
    FAIL() << "misspelt key";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("stifness"), std::string::npos) << e.what();
  }
}

TEST(ParameterSweep, RejectsAnEmptyValueList) {
  EXPECT_THROW(sweep_scenes(scene_path("spring.yaml"), {}, "cloth.springs.structural.stiffness", {}), StudyError);
}

TEST(ParameterValue, ReadsTheFileOrTheLastSetOfTheKey) {
  const std::string path = scene_path("spring.yaml");
  EXPECT_EQ(parameter_value(path, {}, "cloth.springs.structural.stiffness"), 100.0);
  EXPECT_EQ(parameter_value(path, {"cloth.springs.structural.stiffness=5", "cloth.springs.structural.stiffness=9"},
                            "cloth.springs.structural.stiffness"),
            9.0);
  EXPECT_EQ(parameter_value(path, {}, "render.camera.eye.1"), 0.5);  // list items by index
  EXPECT_EQ(parameter_value(path, {}, "air_drag"), std::nullopt);   // absent: its default applies
  EXPECT_EQ(parameter_value(path, {}, "cloth.plane"), std::nullopt);
}

TEST(SetText, KeepsFullPrecision) {
  EXPECT_EQ(set_text("a.b", 0.1), "a.b=0.10000000000000001");
}

}  // namespace
}  // namespace clothsim::analysis
