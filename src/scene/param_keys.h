// The one grammar of a scene parameter named on the command line (compare --vary,
// stability --param): what it sets and what a lane or an axis calls it.
//
//   a dotted path   cloth.springs.structural.stiffness   (any key --set takes)
//   a glob          cloth.springs.*.stiffness             (* for a spring type: every type the
//                                                          scene declares, as the course's one ks)
//   an alias        ks = cloth.springs.*.stiffness, kd = cloth.springs.*.damping
//
// Resolved against the scene, so a glob names only the spring types it builds.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scene_def.h"

namespace clothsim {

struct ParamKeyError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ParamKey {
  std::string label;               // what lanes and axes call it: the alias, else the key as written
  std::vector<std::string> paths;  // the dotted paths it sets, at least one
};

// Throws ParamKeyError (one line, naming the key) for an empty key, a glob elsewhere than a
// spring type, or a glob that matches no spring type of the scene.
ParamKey resolve_param_key(const std::string& key, const SceneDef& scene);

// "PATH=VALUE" for every path of `key`, VALUE at full precision: what --set would say.
std::vector<std::string> param_sets(const ParamKey& key, double value);

// "ks = 2e+04" style text of a value for labels ("ks = 2e4").
std::string param_label(const ParamKey& key, double value);

}  // namespace clothsim
