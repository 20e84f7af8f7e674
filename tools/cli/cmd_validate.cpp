// clothsim validate: parse and check a scene (with --set applied) and say what it models.
// Exit 0 when valid, 2 with the one-line error otherwise; writes nothing.
#include <cmath>
#include <cstdio>

#include "cli_common.h"
#include "commands.h"
#include "memory_budget.h"
#include "memory_estimate.h"
#include "model.h"
#include "scene_options.h"

namespace clothsim::cli {
namespace {

int validate_command(const SceneOptions& o) {
  const SceneDef scene = load_scene_with_options(o);
  // What a run of the scene (no pictures) would need, checked before the Model is built.
  MemoryBudget budget;
  budget.add("model", model_bytes(scene));
  budget.add(std::string(integrator_name(scene.integrator)), run_bytes(scene, scene.integrator));
  budget.check(scene.source, o.max_memory);
  const Model model = build_model(scene);
  int by_type[3] = {0, 0, 0};
  for (SpringType t : model.springs.type) ++by_type[static_cast<int>(t)];
  int pinned = 0;
  for (int p = 0; p < model.num_particles; ++p) pinned += model.initial_inv_mass[p] == 0.0;
  int kinematic = 0;
  for (auto k : model.sphere_kinematic) kinematic += k;
  std::printf("%s: valid scene '%s'\n", scene.source.c_str(), scene.name.c_str());
  std::printf("  cloth: %d x %d particles (%d pinned), %zu springs (structural %d, shear %d, bend %d)\n",
              model.grid_nx, model.grid_ny, pinned, model.springs.size(), by_type[0], by_type[1],
              by_type[2]);
  std::printf("  spheres: %d (%d kinematic, %d dynamic)%s%s\n", model.num_spheres, kinematic,
              model.num_spheres - kinematic, model.has_ground ? ", ground plane" : ", no ground",
              model.air_drag > 0 ? ", air drag" : "");
  std::printf("  run: %s, dt = %g s, %g s (%.0f steps), %zu scripted actions; about %s of memory\n",
              std::string(integrator_name(scene.integrator)).c_str(), scene.dt, scene.duration,
              std::ceil(scene.duration / scene.dt - 1e-9), model.timeline.size(),
              format_bytes(budget.total()).c_str());
  return kOk;
}

}  // namespace

void add_validate_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<SceneOptions>();
  CLI::App* sub = app.add_subcommand("validate", "Check a scene file and summarise what it models");
  add_scene_options(sub, *o, /*single_run=*/true);
  sub->callback([o, &command] { command = [o] { return validate_command(*o); }; });
}

}  // namespace clothsim::cli
