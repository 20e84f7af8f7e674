// clothsim stability SCENE [--integrators LANES] [--param KEY] [--values LIST] [--duration T]
//                          [--set K=V]... [--min-dt S] [--max-dt S] [--precision R]
//                          [--energy-factor F] [--max-strain S] [--csv FILE] [--plot FILE.png]
//                          [--jobs N]
//
// For each integrator and each value of a swept scene key (applied as --set KEY=VALUE after
// the user's own --set), the largest step that runs the scene from 0 to T without
// diverging, found by bisection in log dt (src/study/stability.h). Beside it, the
// Gershgorin estimates 2 / w_max (springs) and 2 / max(w_max, c_max) (dampers counted)
// from src/core/model/stiffness_estimate.h, and each method's margin against them.
//
// Defaults, chosen so `clothsim stability scenes/drape.yaml` takes about a minute on 2 cores:
// the four seed integrators; --param cloth.springs.structural.stiffness at the scene's value
// x 1, 10, 100, 1000, 10000; T = min(scene duration, 0.2 s); steps tried from 1/32 of
// min(scene dt, smallest estimate) up to min(T / 50, 1000 x scene dt) (every trial takes
// at least 50 steps, so an instability has steps to show in); 2 % precision. The
// scene's damping is kept as it is: on the drape (750 N s/m) the dampers, not the springs,
// set the explicit methods' limit until the structural stiffness passes ~4e7 N/m, and the
// second estimate shows it. Sweep damping (--param cloth.springs.structural.damping) or set
// it to 0 on every spring type to see the springs alone.
//
// A trial is stable when it reaches T without diverging and, for implicit_euler, with every
// step's solve converged: a run whose Newton solve missed its tolerance did not compute
// backward Euler, so it fails too, and the CSV's `failure` column says which way a search's
// first failing step failed (diverged | not_converged).
//
// Exit codes: 0; 2 bad options, scene or parameter; 1 I/O or the plot; 130 / 143 an
// interrupted study (SIGINT / SIGTERM: the searches finished so far are written to --csv).
#include <cinttypes>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "clip/studies/stability_outputs.h"
#include "clip/studies/stability_plan.h"
#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/lanes.h"
#include "clip/common/memory_budget.h"
#include "clip/common/scene_options.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/scene_parser.h"
#include "scene/param_keys.h"
#include "study/parameter_sweep.h"
#include "study/stability.h"
#include "study/tables/csv_tables.h"
#include "study/task_pool.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::cli {
namespace {

using analysis::StabilityLimit;
using analysis::StabilityOutcome;

std::string limit_text(const StabilityLimit& l, const analysis::StabilitySpec& spec) {
  char buf[160];
  const bool solve = l.failure == analysis::Failure::NotConverged;  // failed by its solve, not by diverging
  switch (l.outcome) {
    case StabilityOutcome::Bracketed:
      std::snprintf(buf, sizeof buf, "%.4g s (%s at %.4g s)", l.stable_dt, solve ? "NOT CONVERGED" : "diverges",
                    l.unstable_dt);
      break;
    case StabilityOutcome::StableAtMax:
      std::snprintf(buf, sizeof buf, "stable at the largest dt tried (%.4g s)", spec.max_dt);
      break;
    case StabilityOutcome::UnstableAtMin:
      std::snprintf(buf, sizeof buf, "%s at every dt tried (down to %.4g s)",
                    solve ? "NOT CONVERGED" : "unstable", spec.min_dt);
      break;
    case StabilityOutcome::Stopped:
      std::snprintf(buf, sizeof buf, "stopped");
      break;
  }
  return buf;
}

// The limits found, one row per value and integrator.
// Rows labelled as compare labels its lanes (Lane::name).
void print_limits(const std::vector<StabilityLimit>& limits, const analysis::StabilitySpec& spec,
                  const std::vector<Lane>& lanes) {
  std::printf("%14s %-28s %-48s %10s %12s %6s\n", "value", "integrator", "largest stable dt", "x 2/w_max",
              "x 2/max(w,c)", "trials");
  for (const StabilityLimit& l : limits) {
    // The ratios to the estimates only for a bracketed limit ("-" where there is none: the CSV
    // keeps its nan).
    char springs[16] = "-", damping[16] = "-";
    if (l.outcome == StabilityOutcome::Bracketed) {
      std::snprintf(springs, sizeof springs, "%.3g", l.stable_dt / l.estimate.dt_springs());
      std::snprintf(damping, sizeof damping, "%.3g", l.stable_dt / l.estimate.dt_with_damping());
    }
    std::printf("%14.6g %-28s %-48s %10s %12s %6d\n", l.value, lanes[l.lane].name().c_str(),
                limit_text(l, spec).c_str(), springs, damping, l.trials);
    if (l.failure == analysis::Failure::NotConverged)
      std::printf("%14s %-28s NOT CONVERGED at %.4g s: %s\n", "", "", l.unstable_dt, l.reason.c_str());
    if (!l.frame_steps.empty())
      std::printf("%14s %-28s one step per frame: %s\n", "", "", frame_steps_text(l).c_str());
  }
}

int stability_command(const StabilityOptions& o) {
  install_interrupt_handler();  // first: a signal during setup is then seen, not fatal, and temporaries go
  const SceneDef base = load_scene_within(o.scene.path, o.scene.sets, o.scene.max_memory);
  StabilityStudy study = plan_stability(o, base);
  const std::vector<Lane>& lanes = study.lanes;
  const LaneNames& names = study.names;
  const std::vector<IntegratorKind>& kinds = study.spec.integrators;
  const std::vector<double>& values = study.values;
  const std::vector<StabilityCaseModels>& cases = study.cases;
  const analysis::StabilitySpec& spec = study.spec;

  const std::unique_ptr<PlotScript> plot =
      check_study_outputs(o.scene.path, o.csv, o.summary, o.plot, "plot_stability.py");

  std::printf("stability %s: %s over %zu values x %zu integrators, each run 0 to T = %g s; dt tried from %.3g to "
              "%.3g s, bisection to %g %%; unstable = non-finite, strain > %g, or kinetic energy > %g x %.3g J\n",
              base.name.c_str(), o.param.c_str(), values.size(), kinds.size(), spec.duration, spec.min_dt,
              spec.max_dt, 100 * spec.precision, spec.max_strain, spec.energy_factor,
              cases.front().model.energy_scale);
  std::printf("%14s %12s %12s %12s %14s\n", "value", "w_max (1/s)", "2/w_max (s)", "c_max (1/s)", "2/max(w,c) (s)");
  for (const StabilityCaseModels& c : cases) {
    const analysis::StiffnessEstimate e = analysis::estimate_stiffness(c.model);
    std::printf("%14.6g %12.4g %12.4g %12.4g %14.4g\n", c.value, e.w_max, e.dt_springs(), e.c_max, e.dt_with_damping());
  }
  std::fflush(stdout);

  const std::vector<analysis::StabilityCase> refs = study.refs();
  SharedProgress progress("stability " + base.name, static_cast<long>(cases.size() * kinds.size()), "searches");
  analysis::StudyHooks hooks;
  hooks.stop = [] { return interrupted(); };
  hooks.progress = progress.hook();
  if (!o.shard.empty()) {
    const int code = stability_shard(o, base.name, refs, spec, names, hooks);
    progress.finish();  // clears the progress line, as the whole study's end does
    return code;
  }
  const std::vector<StabilityLimit> limits = analysis::stability_sweep(refs, spec, hooks);
  progress.finish();

  print_limits(limits, spec, lanes);

  write_stability_outputs(o, base, limits, study, plot.get());
  return kOk;
}

}  // namespace

void add_stability_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<StabilityOptions>();
  CLI::App* sub = app.add_subcommand(
      "stability", "Largest stable step per integrator across a swept scene parameter (default: stiffness)");
  add_scene_options(sub, o->scene, /*single_run=*/false,
                    "the scene's duration, at most " + csv_number(kStabilityDefaultDuration) + " s");
  sub->add_option("--integrators", o->integrators, "Comma-separated lanes as compare takes them, without @STEP: NAME[:N], implicit_euler_fixed_point, course")
      ->capture_default_str()
      ->type_name("LIST");
  sub->add_option("--param", o->param,
                  "The numeric scene key to sweep: a dotted path, a glob over the spring types (cloth.springs.*.stiffness)\n"
                  "or ks / kd (every spring type's stiffness / damping); the plot's axis is labelled as written")
      ->capture_default_str()
      ->type_name("KEY");
  sub->add_option("--values", o->values,
                  "Comma-separated values of --param (default: the scene's value x 1, 10, 100, 1000, 10000)")
      ->type_name("LIST");
  sub->add_option("--min-dt", o->min_dt,
                  "Smallest step tried, s (default: min(scene dt, the smallest 2/max(w,c) estimate of the swept cases) / " +
                      csv_number(kMinDtDivisor) + ")")
      ->type_name("S");
  sub->add_option("--max-dt", o->max_dt, "Largest step tried, s, at most T / 20 (default: min(T / 50, 1000 x scene dt))")->type_name("S");
  sub->add_option("--frame-dts", o->frame_dts,
                  "Steps implicit_euler is also run at over T, one per video frame (numbers or "
                  "fractions, or 'none'); reported per case, not searched")
      ->capture_default_str()
      ->type_name("LIST");
  sub->add_option("--precision", o->precision, "Relative width of the final bisection bracket")->capture_default_str();
  sub->add_option("--energy-factor", o->energy_factor,
                  "Unstable when kinetic energy exceeds this x the scene's energy scale")
      ->capture_default_str();
  sub->add_option("--max-strain", o->max_strain,
                  "Unstable when a spring is stretched past (1 + this) x its rest length")
      ->capture_default_str();
  sub->add_option("--csv", o->csv, "Write one row per search: param,value,integrator,outcome,stable_dt,...")
      ->type_name("FILE.csv");
  sub->add_option("--plot", o->plot, "Draw largest stable dt vs the parameter (needs python3-matplotlib)")
      ->type_name("FILE.png");
  sub->add_option("--summary", o->summary, "Write each search's result as JSON (docs/summary.md)")
      ->type_name("FILE.json");
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  sub->add_option("--jobs", o->jobs, "Searches at once (default 0: one per core)");
  add_shard_option(sub, o->shard);
  sub->callback([o, &command] { command = [o] { return stability_command(*o); }; });
}

}  // namespace clothsim::cli
