// Models shared by the benchmarks: the shipped drape scene with its cloth resized to N x N
// (same 4 m square, same k = 20000 and d = 750 for all three spring types, same ball).
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::bench {

inline SceneDef drape_scene(int n) {
  const std::string path = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";
  const std::string side = std::to_string(n);
  return load_scene(path, {"cloth.particles=[" + side + "," + side + "]"});
}

inline Model drape_sheet(int n) { return build_model(drape_scene(n)); }

// The barrier drape (scenes/drape_smooth.yaml), its cloth resized to N x N.
inline Model smooth_drape_sheet(int n) {
  const std::string side = std::to_string(n);
  return build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape_smooth.yaml",
                                {"cloth.particles=[" + side + "," + side + "]"}));
}

// A method by its registry name, so the benchmarks name no IntegratorKind. Called inside a
// benchmark's body, never while benchmarks register: the registry is another TU's static.
inline IntegratorKind method(std::string_view name) {
  if (const auto kind = parse_integrator(name)) return *kind;
  throw std::logic_error("benchmark names no integrator: " + std::string(name));
}

}  // namespace clothsim::bench
