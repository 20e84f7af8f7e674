// The options every scene-reading subcommand shares (SCENE, --set, --duration, and for a
// single run --integrator and --dt), and loading a scene with them applied.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scene/scene_def.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

struct SceneOptions {
  std::string path;
  std::vector<std::string> sets;        // --set KEY=VALUE, in order
  std::optional<double> duration;       // --duration S
  std::optional<std::string> integrator;  // --integrator NAME (when offered)
  std::optional<double> dt;             // --dt S (when offered)
  std::optional<int> width, height;     // --width/--height px (when offered): render.width/height
  std::optional<double> fps;            // --fps (when offered): render.fps
  std::optional<double> max_memory;     // --max-memory SIZE in bytes (default: memory_budget.h)
};

// Loads and validates the scene with --set applied, then --duration/--integrator/--dt and
// --width/--height/--fps.
// Throws SceneError (bad scene or --set) or UsageError (bad option value).
SceneDef load_scene_with_options(const SceneOptions& options);

// Parses an integrator name or throws UsageError naming the option and the valid names.
IntegratorKind parse_integrator_option(const std::string& name, const std::string& option);

// "rk4, midpoint" -> integrators in order (spaces around names allowed). An empty list, an
// empty item, an unknown name or a name listed twice is a UsageError naming `option`.
std::vector<IntegratorKind> parse_integrator_list(const std::string& text,
                                                  const std::string& option = "--integrators");

}  // namespace clothsim::clip
