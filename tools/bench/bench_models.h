// Models shared by the benchmarks: the shipped drape scene with its cloth resized to N x N
// (same 4 m square, same k = 20000 and d = 750 for all three spring types, same ball).
#pragma once

#include <string>

#include "core/model.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::bench {

inline SceneDef drape_scene(int n) {
  const std::string path = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";
  const std::string side = std::to_string(n);
  return load_scene(path, {"cloth.particles=[" + side + "," + side + "]"});
}

inline Model drape_sheet(int n) { return build_model(drape_scene(n)); }

}  // namespace clothsim::bench
