// clothsim validate: parse and check a scene (with --set applied) and say what it models,
// with the stiffness estimate `stability` prints (src/core/model/stiffness_estimate.h) and each
// explicit method's predicted step limit from it; a warning on stderr when the scene's dt is
// above one of them. Exit 0 when valid (warned or not), 2 with the one-line error otherwise;
// writes nothing.
#include <cmath>
#include <cstdio>

#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/memory_budget.h"
#include "clip/common/scene_options.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "core/model/stiffness_estimate.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"

namespace clothsim::cli {
namespace {

std::string seconds(double dt) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g s", dt);
  return text;
}

// The estimate 2/w_max (and 2/max(w, c) with the dampers), each explicit method's predicted
// limit, and one warning line naming every method whose limit the scene's dt is above.
void print_step_limits(const SceneDef& scene, const Model& model) {
  const analysis::StiffnessEstimate e = analysis::estimate_stiffness(model);
  if (!(e.w_max > 0.0) && !(e.c_max > 0.0)) {
    std::printf("  step limits: none predicted (no springs or dampers on a free particle)\n");
    return;
  }
  std::printf("  stiffness estimate: w_max = %.4g rad/s, 2/w_max = %s; dampers c_max = %.4g /s, 2/max(w,c) = %s\n",
              e.w_max, seconds(e.dt_springs()).c_str(), e.c_max, seconds(e.dt_with_damping()).c_str());
  std::string limits, above;
  bool own_above = false;
  for (IntegratorKind kind : all_integrators()) {
    const double limit = analysis::predicted_limit(e, kind, scene.implicit);
    // Backward Euler's Newton solve and the solvers' descent on Phi or constraints: no limit.
    if (std::isinf(limit)) continue;
    const bool fixed_point = kind == kBackwardEuler && scene.implicit.solver == ImplicitSolver::FixedPoint;
    std::string name(integrator_name(kind));
    if (fixed_point) name += " (fixed_point, " + std::to_string(scene.implicit.fixed_point_iterations) + " iterations)";
    const std::string value = limit > 0.0 ? seconds(limit) : "none (unstable at every step)";
    limits += (limits.empty() ? "" : ", ") + name + " " + value;
    if (scene.dt > limit) {
      above += (above.empty() ? "" : ", ") + name + " (" + (limit > 0.0 ? value : "unstable at every step") + ")";
      own_above = own_above || kind == scene.integrator;
    }
  }
  const bool newton = scene.implicit.solver == ImplicitSolver::Newton;
  std::printf("  predicted step limits: %s%s\n", limits.c_str(), newton ? "; implicit_euler: none" : "");
  if (above.empty()) return;
  const std::string consequence =
      own_above ? "; the scene's integrator " + std::string(integrator_name(scene.integrator)) + " is likely to diverge" : "";
  std::fflush(stdout);  // the summary first, then the warning, on a terminal as in a log
  std::fprintf(stderr, "clothsim: warning: %s: dt = %g s is above the predicted step limit of %s%s\n",
               scene.source.c_str(), scene.dt, above.c_str(), consequence.c_str());
}

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
  print_step_limits(scene, model);
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
