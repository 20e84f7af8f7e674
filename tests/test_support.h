// Small helpers shared by the test folders: shipped scene paths and inline scenes.
#pragma once

#include <string>
#include <vector>

#include "core/model/model.h"
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

// A 4 x 4 sheet pinned at its corners, lightly damped: stable for symplectic Euler at 1 ms
// (w h ~ 0.3), while explicit Euler at 10 ms (w h > 1.4, growth |1 + i w h| per step) blows up,
// at t = 0.19 s. The frame pipeline's tests run a lane that diverges on it.
inline constexpr const char* kCornerSheet = R"(
name: sheet
dt: 1.0e-3
cloth: {particles: [4, 4], size: [1, 1], pinned: corners,
        springs: {structural: {stiffness: 20000, damping: 5}}}
)";

// A model from YAML text written inline in a test (MuJoCo's tests do the same).
inline Model model_from_yaml(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  return build_model(parse_scene(yaml, "inline.yaml", sets));
}

}  // namespace clothsim::testing
