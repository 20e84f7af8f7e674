#include "scene_options.h"

#include <algorithm>
#include <cmath>

#include "cli_common.h"
#include "install_paths.h"
#include "memory_budget.h"
#include "scene/echo.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

void add_scene_options(CLI::App* sub, SceneOptions& o, bool single_run, const std::string& duration_default) {
  sub->add_option("scene", o.path, "Scene file (YAML; keys in docs/scenes.md), or a shipped scene's name (drape_smooth)")
      ->required()
      ->transform(CLI::Validator(
          [](std::string& arg) {
            arg = resolve_scene_argument(arg);
            return std::string();
          },
          "", "scene"));
  sub->add_option("--set", o.sets,
                  "Override a scene key by its dotted path, e.g. --set cloth.springs.shear.stiffness=1e5 "
                  "(repeatable; VALUE is YAML, so lists work: --set gravity=[0,-1.6,0])")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("--duration", o.duration, "Simulated time in s (default: " + duration_default + ")");
  add_max_memory_option(sub, o.max_memory);
  if (single_run) {
    sub->add_option("--integrator", o.integrator,
                    integrator_names_joined(" | ") + " | " + std::string(kFixedPointName) + " (default: the scene's integrator)");
    // A step of one per frame is said as a fraction (--dt 1/60), which CLI11's double would refuse.
    sub->add_option_function<std::string>(
           "--dt",
           [&o](const std::string& text) {
             const std::optional<double> dt = parse_number_or_fraction(text);
             if (!dt) throw CLI::ValidationError("--dt: " + in_quotes(text) + " is not a number (or a fraction like 1/60)");
             o.dt = *dt;
           },
           "Time step in s, a number or a fraction (1/60) (default: the scene's dt)")
        ->type_name("S");
  }
}

void add_picture_options(CLI::App* sub, SceneOptions& o, const std::string& size_of, const std::string& frames_of) {
  sub->add_option("--width", o.width, "Width of " + size_of + " in pixels (default: the scene's render.width)")
      ->type_name("PX");
  sub->add_option("--height", o.height, "Height of " + size_of + " in pixels (default: the scene's render.height)")
      ->type_name("PX");
  sub->add_option("--fps", o.fps,
                  "Output frames per simulated second: " + frames_of + " (default: the scene's render.fps)")
      ->type_name("F");
}

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
  // --duration and --dt replace the file's values, so the run is bounded once they are in.
  SceneDef scene = load_scene_within(o.path, o.sets, o.max_memory, /*bound_run=*/!(o.duration || o.dt));
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
  if (o.integrator && *o.integrator == kFixedPointName) {  // the course's "implicit", by its own name
    scene.integrator = kBackwardEuler;  // (the fixed point is its solver option)
    scene.implicit.solver = ImplicitSolver::FixedPoint;
  } else if (o.integrator) {
    scene.integrator = parse_integrator_option(*o.integrator, "--integrator");
  }
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
  if (o.duration || o.dt || o.fps) {  // otherwise the parser bounded the file's (and --set's) values
    const std::string too_long = run_bounds_problem(scene.duration, scene.dt, scene.render.fps);
    if (!too_long.empty())
      throw UsageError(std::string(o.dt ? "--dt" : o.duration ? "--duration" : "--fps") + ": " + too_long);
  }
  return scene;
}

}  // namespace clothsim::clip
