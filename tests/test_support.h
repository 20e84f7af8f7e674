// Small helpers shared by the test folders: shipped scene paths and inline scenes.
#pragma once

#include <string>
#include <vector>

#include "core/model.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::testing {

inline std::string scene_path(const std::string& name) {
  return std::string(CLOTHSIM_SCENES_DIR) + "/" + name;
}

inline const std::vector<std::string>& shipped_scenes() {
  static const std::vector<std::string> names{"drape.yaml", "four_balls.yaml", "curtain.yaml",
                                              "spring.yaml", "chain.yaml", "stiff.yaml"};
  return names;
}

// A model from YAML text written inline in a test (MuJoCo's tests do the same).
inline Model model_from_yaml(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  return build_model(parse_scene(yaml, "inline.yaml", sets));
}

}  // namespace clothsim::testing
