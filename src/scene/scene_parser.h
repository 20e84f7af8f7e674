// One parser for scene files: YAML text -> SceneDef, validated. Every key it knows is
// listed in docs/scenes.md with unit and default (the defaults themselves live in
// scene_def.h). Unknown keys, wrong types and out-of-range values are errors that name
// the file, the line and the dotted key, so a user can go straight to the mistake.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scene_def.h"

namespace YAML {
class ParserException;
}

namespace clothsim {

// "FILE:LINE: KEY: what is wrong" (LINE is omitted for a value that came from --set, which
// is named instead: "FILE: --set KEY=VALUE: what is wrong").
struct SceneError : std::runtime_error {
  SceneError(std::string file, int line, std::string key, const std::string& what);
  std::string file;
  int line;  // 1-based; 0 when the error has no line (file unreadable, --set)
  std::string key;  // dotted path, e.g. "cloth.springs.shear.stiffness"
  std::string reason;  // what is wrong, without file and key (to say it of another option)
};

// Reads and validates a scene file. `overrides` are "dotted.key=VALUE" strings (--set),
// VALUE parsed as YAML, applied before validation; a key the schema does not have is an
// error. KEY may also be an alias or a glob (ks, cloth.springs.*.damping: param_keys.h),
// set on every spring type the file declares. Throws SceneError; an unreadable file is a SceneError with line 0.
// `bound_run`: refuse more than kMaxSteps steps or kMaxFrames frames (run_bounds.h); false
// only for a caller that replaces duration or dt (--duration, --dt) and bounds the result.
SceneDef load_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                    bool bound_run = true);

// The 1-based line a YAML parse error of `text` belongs to: where an unclosed '[' or '{'
// opened, for yaml-cpp's "end of ... flow not found" (its own mark is the line after), else
// yaml-cpp's mark; 0 for none. For every YAML file the program reads (scenes, manifests).
int yaml_error_line(const std::string& text, const YAML::ParserException& e);

// Same, from text in memory (tests, and scenes built by tools). `source` names it in errors.
SceneDef parse_scene(const std::string& yaml_text, const std::string& source,
                     const std::vector<std::string>& overrides = {}, bool bound_run = true);

}  // namespace clothsim
