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

TEST(ParamKeys, SetTakesTheSameAliasesAndGlobsAsVaryAndParam) {
  // --set ks=2e6 was "unknown key" while --vary ks and --param ks took it: one alias table now.
  const std::string yaml = "name: s\ncloth: {particles: [3, 3], springs: {structural: {stiffness: 10}, "
                           "shear: {stiffness: 5, damping: 1}}}\n";
  const SceneDef s = parse_scene(yaml, "inline.yaml", {"ks=2e6", "cloth.springs.*.damping=3"});
  ASSERT_TRUE(s.cloth.structural && s.cloth.shear);
  EXPECT_EQ(s.cloth.structural->stiffness, 2e6);
  EXPECT_EQ(s.cloth.shear->stiffness, 2e6);
  EXPECT_EQ(s.cloth.structural->damping, 3.0);
  EXPECT_EQ(s.cloth.shear->damping, 3.0);
  EXPECT_FALSE(s.cloth.bend) << "a type the scene does not declare is not built by an alias";
}

TEST(ParamKeys, SetOfAnAliasOverNoSpringsOrABadValueNamesTheSetAsTyped) {
  try {
    parse_scene("name: s\ncloth: {particles: [3, 3]}\n", "inline.yaml", {"kd=1"});
    FAIL() << "no springs: nothing for kd";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key, "--set kd=1");
    EXPECT_NE(std::string(e.what()).find("'kd' matches nothing"), std::string::npos) << e.what();
  }
  try {
    parse_scene("name: s\ncloth: {particles: [3, 3], springs: {structural: {stiffness: 10}}}\n", "inline.yaml",
                {"ks=-4"});
    FAIL() << "a negative stiffness";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("--set ks=-4"), std::string::npos) << e.what();
  }
}

TEST(ParamKeys, AnErrorInAKeysSetIsSaidOfTheOptionTyped) {
  // --vary kss=1,2 said "--set kss=1: unknown key": the user wrote --vary.
  const std::string yaml = "name: s\ncloth: {particles: [3, 3], springs: {structural: {stiffness: 10}}}\n";
  const ParamKey kss = resolve_param_key("kss", parse_scene(yaml, "inline.yaml"));
  try {
    parse_scene(yaml, "inline.yaml", param_sets(kss, 1.0));
    FAIL() << "kss is no scene key";
  } catch (const SceneError& e) {
    const SceneError said = as_option_error(e, kss, "--vary kss=1,2");
    EXPECT_EQ(said.key, "--vary kss=1,2");
    EXPECT_EQ(std::string(said.what()).rfind("inline.yaml: --vary kss=1,2: unknown key", 0), 0u) << said.what();
    const SceneError other = as_option_error(e, resolve_param_key("ks", parse_scene(yaml, "inline.yaml")), "--vary ks");
    EXPECT_EQ(other.key, e.key) << "an error about another key is left as it is";
  }
}
