// A scene with one numeric key swept: one validated SceneDef per value, each loaded as if
// the user had typed --set KEY=VALUE after their own --set options.
//
// "Numeric" is decided by the parser, the one place that knows the schema: the key must
// accept the sweep's numbers, and must reject a word (a key that takes text, such as
// `name`, would accept the numbers as text and sweep nothing). A key the schema does not
// have is the parser's own error (it names the key and what is expected instead).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "study.h"
#include "scene/scene_def.h"

namespace clothsim::analysis {

struct SweepScene {
  double value = 0.0;
  SceneDef scene;
};

// Throws StudyError when `param` is not numeric or `values` is empty or non-finite, and
// SceneError (scene_parser.h) when the file, a --set or a value is rejected.
std::vector<SweepScene> sweep_scenes(const std::string& path, const std::vector<std::string>& sets,
                                     const std::string& param, const std::vector<double>& values);
// The same with every key of `params` set to each value (a glob or an alias resolved by
// scene/param_keys.h: the course's one ks is three keys).
std::vector<SweepScene> sweep_scenes(const std::string& path, const std::vector<std::string>& sets,
                                     const std::vector<std::string>& params, const std::vector<double>& values);

// The value the scene file (or the last --set of the key) gives `param`, if it gives one as
// a number; nullopt when the key is absent (its default applies) or not a number.
std::optional<double> parameter_value(const std::string& path, const std::vector<std::string>& sets,
                                      const std::string& param);

// "KEY=VALUE" with VALUE at full precision.
std::string set_text(const std::string& param, double value);

}  // namespace clothsim::analysis
