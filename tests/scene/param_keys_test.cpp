// One KEY grammar for compare --vary and stability --param: paths, globs over spring types,
// the aliases ks and kd.
#include "scene/param_keys.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace clothsim;

namespace {

SceneDef scene_with(const std::string& springs) {
  return parse_scene("name: s\ncloth: {particles: [3, 3], springs: {" + springs + "}}\n", "inline.yaml");
}

}  // namespace

TEST(ParamKeys, ADottedPathIsItself) {
  const ParamKey k = resolve_param_key("cloth.particle_mass", scene_with("structural: {stiffness: 10}"));
  EXPECT_EQ(k.label, "cloth.particle_mass");
  EXPECT_EQ(k.paths, (std::vector<std::string>{"cloth.particle_mass"}));
}

TEST(ParamKeys, AGlobAndItsAliasNameEverySpringTypeTheSceneBuilds) {
  const SceneDef s = scene_with("structural: {stiffness: 10}, bend: {stiffness: 5}");
  const std::vector<std::string> both{"cloth.springs.structural.stiffness", "cloth.springs.bend.stiffness"};
  EXPECT_EQ(resolve_param_key("cloth.springs.*.stiffness", s).paths, both);
  const ParamKey ks = resolve_param_key("ks", s);
  EXPECT_EQ(ks.paths, both);
  EXPECT_EQ(ks.label, "ks");
  EXPECT_EQ(resolve_param_key("kd", s).paths,
            (std::vector<std::string>{"cloth.springs.structural.damping", "cloth.springs.bend.damping"}));
}

TEST(ParamKeys, AGlobElsewhereOrOverNoSpringsIsRefusedNamingTheKey) {
  const SceneDef s = scene_with("structural: {stiffness: 10}");
  EXPECT_THROW(resolve_param_key("spheres.*.radius", s), ParamKeyError);
  EXPECT_THROW(resolve_param_key("cloth.springs.*.*", s), ParamKeyError);
  EXPECT_THROW(resolve_param_key("", s), ParamKeyError);
  const SceneDef bare = parse_scene("name: s\ncloth: {particles: [3, 3]}\n", "inline.yaml");
  try {
    resolve_param_key("ks", bare);
    FAIL() << "no springs: nothing to set";
  } catch (const ParamKeyError& e) {
    EXPECT_NE(std::string(e.what()).find("'ks' matches nothing"), std::string::npos) << e.what();
  }
}

TEST(ParamKeys, SetsEveryPathAndLabelsTheValueShortly) {
  const ParamKey ks = resolve_param_key("ks", scene_with("structural: {stiffness: 10}, shear: {stiffness: 10}"));
  EXPECT_EQ(param_sets(ks, 2e4), (std::vector<std::string>{"cloth.springs.structural.stiffness=20000",
                                                           "cloth.springs.shear.stiffness=20000"}));
  EXPECT_EQ(param_label(ks, 2e4), "ks = 2e4");
  EXPECT_EQ(param_label(ks, 2000), "ks = 2000");
  EXPECT_EQ(param_label(ks, 1.5e-5), "ks = 1.5e-5");
  EXPECT_EQ(param_label(ks, 0.5), "ks = 0.5");
}
