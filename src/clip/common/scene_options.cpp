#include "scene_options.h"

#include <algorithm>
#include <cmath>

#include "cli_common.h"
#include "install_paths.h"
#include "lanes.h"
#include "memory_budget.h"
#include "scene/echo.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

IntegratorKind parse_integrator_option(const std::string& name, const std::string& option) {
  const auto kind = parse_integrator(name);
  if (!kind)
    throw UsageError(option + ": unknown integrator " + in_quotes(name) + " (expected one of: " +
                     integrator_names_joined() + ")");
  return *kind;
}

std::vector<IntegratorKind> parse_integrator_list(const std::string& text, const std::string& option) {
  std::vector<IntegratorKind> kinds;
  for (const std::string& raw : split_list(text)) {
    const auto begin = raw.find_first_not_of(" \t");
    const std::string name =
        begin == std::string::npos ? "" : raw.substr(begin, raw.find_last_not_of(" \t") - begin + 1);
    if (name.empty()) throw UsageError(option + ": empty item in " + in_quotes(text));
    const IntegratorKind kind = parse_integrator_option(name, option);
    if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end())
      throw UsageError(option + ": " + in_quotes(name) + " is listed twice");
    kinds.push_back(kind);
  }
  if (kinds.empty())
    throw UsageError(option + ": empty list, no integrator given (expected names such as rk4,implicit_euler)");
  return kinds;
}

SceneDef load_scene_with_options(const SceneOptions& o) {
  // --integrator is a lane (scene/lane.h), parsed once, before the scene: its @STEP replaces the
  // file's dt as --dt does.
  std::optional<Lane> lane;
  if (o.integrator) {
    try {
      lane = parse_lane(*o.integrator);
    } catch (const LaneError& e) {
      refuse_lane("--integrator", e);
    }
    if (lane->written_step() && o.dt)
      throw UsageError("--integrator: " + in_quotes(*o.integrator) + " gives the step, and so does --dt: give it in one place");
  }
  const bool new_step = o.dt || (lane && lane->written_step());
  // --duration and --dt replace the file's values, so the run is bounded once they are in.
  SceneDef scene = load_scene_within(o.path, o.sets, o.max_memory, /*bound_run=*/!(o.duration || new_step));
  if (o.duration) {
    if (!(*o.duration >= 0.0) || !std::isfinite(*o.duration))
      throw UsageError("--duration: must be a finite number >= 0 s, got " + number_text(*o.duration));
    scene.duration = *o.duration;
  }
  if (o.dt) {
    if (!(*o.dt > 0.0) || !std::isfinite(*o.dt))
      throw UsageError("--dt: must be a finite number > 0 s, got " + number_text(*o.dt));
    scene.dt = *o.dt;
  }
  if (lane) apply_lane(scene, *lane);  // the method, its step and its settings, as the scene's own
  // The scene parser's bounds for render.width/height/fps (RenderDef), said as options.
  const auto pixels = [](std::optional<int> v, const char* option, int& out) {
    if (!v) return;
    if (*v < RenderDef::kMinSize || *v > RenderDef::kMaxSize)
      throw UsageError(std::string(option) + ": must be from " + std::to_string(RenderDef::kMinSize) + " to " +
                       std::to_string(RenderDef::kMaxSize) + " pixels, got " + std::to_string(*v));
    out = *v;
  };
  pixels(o.width, "--width", scene.render.width);
  pixels(o.height, "--height", scene.render.height);
  if (o.fps) {
    if (!(*o.fps > 0.0) || !std::isfinite(*o.fps) || *o.fps > RenderDef::kMaxFps)
      throw UsageError("--fps: must be > 0 and <= " + std::to_string(static_cast<int>(RenderDef::kMaxFps)) +
                       " frames per second, got " + number_text(*o.fps));
    scene.render.fps = *o.fps;
  }
  if (o.duration || new_step || o.fps) {  // otherwise the parser bounded the file's (and --set's) values
    const std::string too_long = run_bounds_problem(scene.duration, scene.dt, scene.render.fps);
    if (!too_long.empty())
      throw UsageError(std::string(o.dt ? "--dt" : new_step ? "--integrator" : o.duration ? "--duration" : "--fps") + ": " + too_long);
  }
  return scene;
}

}  // namespace clothsim::clip
