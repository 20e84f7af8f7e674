// clothsim converge SCENE [--dt S] [--integrators LIST] [--states K] [--max-iterations N]
//                        [--csv F] [--plot F.png] [--summary F.json] [--shard K/N|auto]
// The iterative methods against the step they approximate (study/convergence.h): from K states
// along a converged run (implicit_euler's for the solvers, each implicit family method's own),
// one step of every method with 1..N iterations, its distance from the converged step (backward
// Euler's, or the method's own), Phi's gradient norm and its CPU time.
// With --shard, this process's part of the (state, method) sweeps (study_shard.h).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "clip/studies/converge_outputs.h"
#include "clip/studies/converge_plan.h"
#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/lanes.h"
#include "clip/common/scene_options.h"
#include "scene/build_model.h"
#include "scene/echo.h"
#include "study/convergence.h"

namespace clothsim::cli {
namespace {

// The fewest iterations (and their CPU) whose mean RMS distance is within `tolerance`.
std::string first_within(const std::map<std::pair<int, int>, ConvergeMean>& table, IntegratorKind k, double tolerance) {
  for (const auto& [key, m] : table)
    if (key.first == static_cast<int>(k) && m.rms <= tolerance) {
      char text[64];
      std::snprintf(text, sizeof text, "%4d it, %8.3g s", key.second, m.cpu);
      return text;
    }
  return "     not reached";
}

// The iteration counts at which some state's step read WRONG ("-" for none), and the first reason.
std::string wrong_text(const std::vector<ConvergencePoint>& points, IntegratorKind k) {
  int first = 0, last = 0;
  std::string why;
  for (const ConvergencePoint& p : points)
    if (p.method == k && !p.wrong.empty()) {
      if (first == 0 || p.iterations < first) first = p.iterations, why = p.wrong;
      last = std::max(last, p.iterations);
    }
  if (first == 0) return "-";
  return "WRONG at " + std::to_string(first) + (last > first ? ".." + std::to_string(last) : "") + " it: " + why;
}

void print_table(const ConvergenceSpec& spec, const std::vector<ConvergencePoint>& points) {
  const auto table = converge_means(points);
  std::printf("%-20s %12s %12s   %-18s %-18s %s\n", "method", "rms@1 it (m)", "rms@N it (m)", "to 1 cm", "to 1 mm",
              "wrong");
  for (IntegratorKind k : spec.methods) {
    const ConvergeMean first = table.at({static_cast<int>(k), 1}), last = table.at({static_cast<int>(k), spec.max_iterations});
    std::printf("%-20s %12.3g %12.3g   %-18s %-18s %s\n", std::string(integrator_name(k)).c_str(), first.rms,
                last.rms, first_within(table, k, 1e-2).c_str(), first_within(table, k, 1e-3).c_str(),
                wrong_text(points, k).c_str());
  }
}

int converge_command(const ConvergeOptions& o) {
  install_interrupt_handler();
  const SceneDef scene = load_scene_with_options(o.scene);
  const ConvergenceSpec spec = plan_converge(o);
  refuse_clashing_paths({{o.scene.path, "the scene"}}, {{o.csv, "--csv"}, {o.plot, "--plot"}, {o.summary, "--summary"}});
  for (const auto& [path, what] : {std::pair{o.csv, "--csv"}, {o.summary, "--summary"}})
    if (!path.empty()) require_writable_parent(path, what);
  const Model model = build_model(scene);
  const long sweeps = static_cast<long>(spec.states * spec.methods.size());
  SharedProgress progress("converge " + model.name, sweeps, "sweeps");
  analysis::StudyHooks hooks;
  hooks.stop = [] { return interrupted(); };
  hooks.progress = progress.hook();
  if (!o.shard.empty()) return converge_shard(o, model, spec, hooks);
  std::unique_ptr<PlotScript> plot;
  if (!o.plot.empty()) plot = std::make_unique<PlotScript>("plot_convergence.py", o.plot);
  std::printf("converge %s: %d states at dt = %s s, %zu methods x 1..%d iterations, against converged "
              "backward Euler (the implicit family: its own converged step)\n", model.name.c_str(), spec.states, step_string(spec.h).c_str(), spec.methods.size(),
              spec.max_iterations);
  std::fflush(stdout);
  const auto points = convergence_study(model, spec, hooks);
  progress.finish();
  const std::size_t finished = points.size() / static_cast<std::size_t>(spec.max_iterations);
  if (finished < static_cast<std::size_t>(sweeps)) {  // the finished sweeps' rows stay, marked incomplete
    write_converge_outputs(o, scene.source, model, spec, points, nullptr);
    throw RuntimeFailure(study_interrupted_message(finished, sweeps, "sweeps", {o.csv, o.summary}, o.plot));
  }
  print_table(spec, points);
  write_converge_outputs(o, scene.source, model, spec, points, plot.get());
  return kOk;
}

}  // namespace

void add_converge_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<ConvergeOptions>();
  CLI::App* sub = app.add_subcommand(
      "converge", "Distance of xpbd, projective_dynamics, vbd and capped Newton from converged backward Euler "
                  "(the implicit family from its own step), per iteration and CPU");
  add_scene_options(sub, o->scene, /*single_run=*/false);
  sub->add_option("--dt", o->dt, "Step, s (a number or a fraction)")->capture_default_str()->type_name("S");
  sub->add_option("--integrators", o->integrators, "Iterative methods")->capture_default_str()->type_name("LIST");
  sub->add_option("--states", o->states, "States along the converged run")->capture_default_str()->type_name("K");
  sub->add_option("--max-iterations", o->max_iterations, "Iterations 1..N per method")
      ->capture_default_str()->type_name("N");
  sub->add_option("--csv", o->csv, "One row per method, state and iteration count")->type_name("FILE.csv");
  sub->add_option("--plot", o->plot, "Distance against iterations and CPU, log-log (python3-matplotlib)")
      ->type_name("FILE.png");
  sub->add_option("--summary", o->summary, "Mean distance and CPU per method and iteration as JSON")
      ->type_name("FILE.json");
  add_shard_option(sub, o->shard);
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  sub->callback([o, &command] { command = [o] { return converge_command(*o); }; });
}

}  // namespace clothsim::cli
