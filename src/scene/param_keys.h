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
#include "scene_parser.h"

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

// The same expansion given the spring types a scene declares (in the parser's order), for
// the parser's --set, which meets a key before there is a SceneDef: so --set ks=2e6,
// --vary ks=... and --param ks share one alias table. `source` names the scene in errors.
std::vector<std::string> param_paths(const std::string& key, const std::vector<std::string>& spring_types,
                                     const std::string& source);

// Whether `key` needs param_paths (an alias or a glob), rather than being a path itself.
bool is_param_pattern(const std::string& key);

// A parser error met while applying `key`'s sets, said as the option the user typed
// (`option`, e.g. "--vary kss=1,2") when it is about one of key's paths: the user wrote
// --vary, not the --set it became. Any other error is returned as it is.
SceneError as_option_error(const SceneError& e, const ParamKey& key, const std::string& option);

// "PATH=VALUE" for every path of `key`, VALUE at full precision: what --set would say.
std::vector<std::string> param_sets(const ParamKey& key, double value);

// "ks = 2e+04" style text of a value for labels ("ks = 2e4"), in `digits` significant figures
// (3 to 17) where the value is written with its exponent, at least 6 where it is not.
std::string param_label(const ParamKey& key, double value, int digits = 3);

}  // namespace clothsim
