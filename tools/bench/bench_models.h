// Models shared by the benchmarks: the shipped drape scene with its cloth resized to N x N
// (same 4 m square, same k = 20000 and d = 750 for all three spring types, same ball).
#pragma once

#include <string>

#include "model.h"
#include "scene_parser.h"

namespace clothsim::bench {

inline Model drape_sheet(int n) {
  const std::string path = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";
  const std::string side = std::to_string(n);
  return build_model(load_scene(path, {"cloth.particles=[" + side + "," + side + "]"}));
}

}  // namespace clothsim::bench
