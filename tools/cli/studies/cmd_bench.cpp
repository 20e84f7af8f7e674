// clothsim bench SCENE [--integrators LANES] [--dts LIST] [--tols LIST] [--duration T] [--set K=V]...
//                      [--csv FILE] [--plot FILE.png] [--jobs N] [--reference-refinement N]
//
// The work-precision study (src/study/work_precision.h): every integrator at every step
// size (an adaptive pair at every --tols tolerance) runs the scene to T; its cloth positions are
// compared with a reference the program computes at the study's sample times (judged by the
// largest, or at T with --error end), and its cost recorded (wall and CPU time, force
// evaluations). Runs spread over the cores, longest first; a diverged run stops early.
//
// Defaults, chosen so `clothsim bench scenes/drape.yaml` takes about a minute on 2 cores:
// the four seed integrators; six steps from a quarter of the scene's dt to eight times it
// (scenes set dt near the explicit methods' limit, so the list shows both sides of it), and
// an adaptive lane (bs3, dopri5, rkf78) at six tolerances, 1e-3 to 1e-8 (--tols);
// T = min(scene duration, 0.5 s, 8000 x the smallest step), rounded down to a multiple of
// the largest step so that every step divides it. The reference costs 16 x 8000 RK4 steps
// at most, which is what bounds T.
//
// Exit codes: 0; 2 bad options or scene; 1 I/O, the plot, or a reference that is not
// converged (the CSV is still written, so the figures can be inspected, but no plot is
// drawn); 130 / 143 an interrupted study (SIGINT / SIGTERM: the runs finished so far are
// written to --csv).
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/studies/bench_budget.h"
#include "clip/studies/bench_outputs.h"
#include "clip/studies/bench_plan.h"
#include "clip/studies/budget_plan.h"
#include "clip/studies/study_common.h"
#include "clip/studies/study_shard.h"
#include "clip/common/cli_common.h"
#include "cli/common/commands.h"
#include "cli/common/options.h"
#include "clip/common/lanes.h"
#include "clip/common/memory_budget.h"
#include "clip/common/scene_options.h"
#include "clip/common/plan_parts.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/param_keys.h"
#include "scene/scene_parser.h"
#include "study/reference.h"
#include "study/scale_study.h"
#include "study/task_pool.h"
#include "study/work_precision.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::cli {
namespace {

using analysis::WorkPrecisionPoint;

// Rows and orders labelled as compare labels its lanes (Lane::name), or by `labels` (--vary:
// "rk4 (ks = 2e4)").
void print_table(const WorkPrecisionResult& r, const std::vector<Lane>& lanes, const LaneNames& labels = {}) {
  const auto label = [&](std::size_t i) { return labels.empty() ? lanes[i].name() : labels[i]; };
  if (r.reference.over_time)
    std::printf("errors: the largest over %d sample times, every %g s to T (L-infinity in time; --error end: at T alone)\n",
                r.reference.samples, r.duration / r.reference.samples);
  else
    std::printf("errors: at T = %g s alone (--error end)\n", r.duration);
  std::printf("%-28s %10s %8s %11s %9s %9s %12s %12s  %s\n", "integrator", "dt (s)", "steps", "force evals",
              "wall (s)", "cpu (s)", "rms err (m)", "max err (m)", "status");
  for (const WorkPrecisionPoint& p : r.points) {
    char status[160];
    if (p.diverged) std::snprintf(status, sizeof status, "DIVERGED at t = %.4g s: %s", p.diverged_at, p.reason.c_str());
    else if (p.unconverged_steps > 0)
      std::snprintf(status, sizeof status, "NOT CONVERGED: %" PRId64 " of %" PRId64 " steps", p.unconverged_steps, p.steps);
    else if (p.wrong) std::snprintf(status, sizeof status, "WRONG at t = %.4g s: %s", p.wrong_at, p.wrong_reason.c_str());
    else if (p.unresolved)
      std::snprintf(status, sizeof status, "unresolved: under %g x the reference's error", 1.0 / r.reference.margin);
    else std::snprintf(status, sizeof status, "ok");
    char rms[32] = "-", max[32] = "-";  // an unresolved error is no number
    if (!p.unresolved) std::snprintf(rms, sizeof rms, "%.4g", p.rms_error), std::snprintf(max, sizeof max, "%.4g", p.max_error);
    char step[32];  // an adaptive point is by its tolerance: its steps are its own
    if (p.tolerance > 0.0) std::snprintf(step, sizeof step, "tol %.0e", p.tolerance);
    else std::snprintf(step, sizeof step, "%.4g", p.dt);
    std::printf("%-28s %10s %8" PRId64 " %11" PRId64 " %9.3g %9.3g %12s %12s  %s\n",
                label(p.lane).c_str(), step, p.steps, p.force_evals,
                p.wall_seconds, p.cpu_seconds, rms, max, status);
  }
  // Fixed steps: the order; adaptive lanes: how the error follows the tolerance (1: in step).
  for (const bool adaptive : {false, true}) {
    std::string line;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      if (integrator_info(lanes[i].kind).adaptive != adaptive) continue;
      const double order = analysis::lane_convergence_order(r.points, i);
      char item[96];
      if (std::isnan(order)) std::snprintf(item, sizeof item, "  %s -", label(i).c_str());
      else std::snprintf(item, sizeof item, "  %s %.2f", label(i).c_str(), order);
      line += item;
    }
    if (line.empty()) continue;
    std::printf("%s%s\n",
                adaptive ? "error against tolerance (slope of log rms error vs log tol, runs that finished):"
                         : "observed order (slope of log rms error vs log dt, runs that finished, common steps):",
                line.c_str());
  }
  for (std::size_t i = 0; i < lanes.size(); ++i)  // an order well below the method's, explained
    for (const std::string& why : analysis::lane_order_shortfall(r, i, lanes[i].kind))
      std::printf("%s below its order %d: %s\n", label(i).c_str(), analysis::nominal_order(lanes[i].kind), why.c_str());
  const std::vector<analysis::ParetoLevel> front = analysis::pareto_front(r.points);
  if (front.empty()) return;
  std::printf("cheapest to each error level (least CPU among the runs that finished, converged, resolved, not WRONG):\n");
  for (const analysis::ParetoLevel& level : front) {
    const WorkPrecisionPoint& p = r.points[level.point];
    char step[32];
    if (p.tolerance > 0.0) std::snprintf(step, sizeof step, "tol %-9.0e", p.tolerance);
    else std::snprintf(step, sizeof step, "dt %-10.4g", p.dt);
    std::printf("  rms err <= %-8.0e %-28s %s %9.3g s CPU  %11" PRId64 " force evals  (%.3g m)\n", level.level,
                label(p.lane).c_str(), step, p.cpu_seconds, p.force_evals, p.rms_error);
  }
}

void print_reference_check(const analysis::ReferenceCheck& ref) {
  if (!ref.finished) return;
  if (ref.adaptive)
    std::printf("reference check: tightening the adaptive reference's tolerance (dopri5, %g -> %g) moved the "
                "particles by %.3g m RMS (%.3g m max): its estimated error",
                ref.tolerance, ref.tolerance / analysis::kReferenceTightening, ref.change_rms, ref.change_max);
  else
    std::printf("reference check: halving the reference step (%s, %g s -> %g s) moved the particles by %.3g m RMS "
                "(%.3g m max): its estimated error",
                std::string(integrator_name(ref.integrator)).c_str(), 2 * ref.dt, ref.dt, ref.change_rms, ref.change_max);
  if (!std::isnan(ref.smallest_error))
    std::printf("; the smallest error resolved is %.3g m RMS, %.3g times larger", ref.smallest_error,
                ref.change_rms > 0 ? ref.smallest_error / ref.change_rms : INFINITY);
  if (ref.unresolved > 0)
    std::printf("; %d run%s under %g x it unresolved%s", ref.unresolved, ref.unresolved == 1 ? "" : "s",
                1.0 / ref.margin, ref.change_rms <= ref.round_off ? " (at round-off, as the reference is)" : "");
  std::printf("; the two runs took %" PRId64 " steps, %" PRId64 " force evaluations, %.3g s CPU\n", ref.steps,
              ref.force_evals, ref.cpu_seconds);
  if (ref.cache == "reused")
    std::printf("reference: reused from the cache (%s), computed there in %.3g s of CPU\n", ref.cache_file.c_str(),
                ref.cpu_seconds);
  else if (ref.cache == "stored")
    std::printf("reference: computed, and stored in the cache (%s)\n", ref.cache_file.c_str());
  else if (ref.cache == "off")
    std::printf("reference: computed (the cache is off: --no-reference-cache, or CLOTHSIM_REFERENCE_CACHE_MAX=0)\n");
  else
    std::printf("reference: computed, %s\n", ref.cache.c_str());
}

// One value's study, run and its table printed; returns the runs it planned.
std::size_t run_value(const BenchOptions& o, const std::vector<Lane>& lanes, ValueStudy& s) {
  const BenchModels models(o, s.scene, lanes, s.spec);
  const Model& model = models.model;
  const WorkPrecisionSpec& spec = models.spec;
  std::printf("bench %s, %s: %zu lanes x %zu steps to T = %g s\n", model.name.c_str(), s.label.c_str(), lanes.size(),
              spec.dts.size(), spec.duration);
  std::fflush(stdout);
  const std::size_t planned = analysis::planned_points(spec).size();
  SharedProgress progress("bench " + model.name + ", " + s.label, static_cast<long>(planned + 2), "runs");
  analysis::StudyHooks hooks;
  hooks.stop = [] { return interrupted(); };
  hooks.progress = progress.hook();
  s.result = analysis::work_precision(model, spec, hooks);
  progress.finish();
  print_table(s.result, lanes, s.names);
  print_reference_check(s.result.reference);
  return planned;
}

int bench_variation(const BenchOptions& o, const SceneDef& base, const std::vector<Lane>& lanes) {
  std::vector<ValueStudy> studies = plan_values(o, base, lanes);
  const std::unique_ptr<PlotScript> plot = check_study_outputs(o.scene.path, o.csv, "", o.plot, "plot_work_precision.py");
  std::size_t done = 0, runs = 0;
  std::string failure;  // a value whose reference did not converge
  for (ValueStudy& s : studies) {
    runs += run_value(o, lanes, s);
    done += s.result.points.size();
    if (interrupted() || !s.result.complete) break;
    if (!s.result.reference.converged && failure.empty()) failure = s.label + ": " + s.result.reference.failure;
  }
  write_values_outputs(o, base, studies, done, runs, failure, plot.get());
  return kOk;
}

// --scale N1,N2,...: cost against sheet size (bench_plan.h), its table as each point finishes.
int bench_scale(const BenchOptions& o) {
  install_interrupt_handler();
  const ScalePlan scale = plan_scale(o);
  const analysis::ScaleSpec& spec = scale.spec;
  const std::vector<Lane>& lanes = *scale.lanes;
  const std::vector<int>& sides = scale.sides;
  const SceneDef& first = spec.sizes.front().scene;
  const std::unique_ptr<PlotScript> plot = check_study_outputs(o.scene.path, o.csv, "", o.plot, "plot_scale.py");
  check_scale_memory(o, scale);
  std::printf("bench %s --scale: %zu lanes x %zu sizes to T = %g s, total mass %g kg fixed\n", first.name.c_str(),
              lanes.size(), sides.size(), spec.duration, first.cloth.particle_mass * sides.front() * sides.front());
  std::printf("%-28s %6s %10s %12s %10s %12s %10s %10s  %s\n", "lane", "side", "cpu (s)", "cpu / sim s",
              "newton/st", "linear/newt", "est (MB)", "rss (MB)", "status");
  std::fflush(stdout);
  analysis::StudyHooks hooks;
  hooks.stop = [] { return interrupted(); };
  const std::vector<analysis::ScalePoint> points = analysis::scale_study(spec, hooks, [&](const analysis::ScalePoint& p) {
    std::printf("%-28s %6d %10.3g %12.4g %10.3g %12.3g %10.1f %10.1f  %s\n", spec.lanes[p.lane].name.c_str(), p.side,
                p.totals.cpu_seconds, p.cpu_per_simulated_second(), p.newton_per_step(), p.linear_per_newton(),
                p.memory_estimate / (1 << 20), p.peak_rss / (1 << 20), p.finished ? "ok" : ("stopped: " + p.reason).c_str());
    std::fflush(stdout);
  });
  std::printf("fitted exponent p of CPU / simulated s ~ particles^p (1: linear):");
  for (std::size_t i = 0; i < lanes.size(); ++i)
    std::printf("  %s %.2f", spec.lanes[i].name.c_str(), analysis::scale_exponent(points, i));
  std::printf("\n");
  write_scale_outputs(o, scale, points, plot.get());
  return kOk;
}

int bench_command(const BenchOptions& o) {
  if (!o.budget.empty()) return bench_budget(o);
  if (o.scene.fps) throw UsageError("--fps: the frame of --budget; give --budget N with it");
  if (!o.scale.empty()) return bench_scale(o);
  install_interrupt_handler();  // first: a signal during setup is then seen, not fatal, and temporaries go
  SceneDef scene = load_scene_within(o.scene.path, o.scene.sets, o.scene.max_memory);
  const std::vector<Lane> lanes = bench_lanes(o, scene);
  if (!o.vary.empty()) return bench_variation(o, scene, lanes);
  std::vector<IntegratorKind> kinds;
  for (const Lane& l : lanes) kinds.push_back(l.kind);
  const WorkPrecisionSpec plan = plan_bench(o, scene, lanes);
  const double T = plan.duration;

  // Outputs are checked (and python/matplotlib found) before minutes of simulation.
  const std::unique_ptr<PlotScript> plot =
      check_study_outputs(o.scene.path, o.csv, o.summary, o.plot, "plot_work_precision.py");

  const BenchModels models(o, scene, lanes, plan);  // with the lanes' own solver settings
  const Model& model = models.model;
  const WorkPrecisionSpec& spec = models.spec;
  const LaneNames& names = spec.lane_names;
  const double h_ref = spec.dts.front() / spec.reference_refinement;
  const std::size_t runs = analysis::planned_points(spec).size();
  char reference[160];
  if (analysis::uses_adaptive_reference(model, spec))
    std::snprintf(reference, sizeof reference, "adaptive dopri5 at tolerances %g and %g", spec.reference_tolerance,
                  spec.reference_tolerance / analysis::kReferenceTightening);
  else
    std::snprintf(reference, sizeof reference, "%s at %g s and %g s",
                  std::string(integrator_name(spec.reference_integrator)).c_str(), h_ref, h_ref / 2);
  char tolerances[96] = "";
  if (!spec.tolerances.empty())
    std::snprintf(tolerances, sizeof tolerances, ", adaptive lanes x %zu tolerances (%g .. %g)", spec.tolerances.size(),
                  spec.tolerances.front(), spec.tolerances.back());
  const bool frame_steps = std::any_of(lanes.begin(), lanes.end(), [&](const Lane& l) {
    return integrator_info(l.kind).frame_rate_steps && !spec.frame_dts.empty();
  });
  std::printf("bench %s: %zu integrators x %zu steps (%g .. %g s)%s%s to T = %g s on %d threads; reference %s\n",
              model.name.c_str(), kinds.size(), spec.dts.size(), spec.dts.front(), spec.dts.back(), tolerances,
              frame_steps ? ", implicit_euler also at one step per frame" : "", T,
              std::min<int>(analysis::resolve_jobs(o.jobs), static_cast<int>(runs + 2)), reference);
  std::fflush(stdout);

  SharedProgress progress("bench " + model.name, static_cast<long>(runs + 2), "runs");
  analysis::StudyHooks hooks;
  hooks.stop = [] { return interrupted(); };
  hooks.progress = progress.hook();
  if (!o.shard.empty()) {
    const int code = bench_shard(o, model, spec, names, hooks);
    progress.finish();  // clears the progress line, as the whole study's end does
    return code;
  }
  const WorkPrecisionResult result = analysis::work_precision(model, spec, hooks);
  progress.finish();

  print_table(result, lanes);
  const analysis::ReferenceCheck& ref = result.reference;
  print_reference_check(ref);

  write_bench_outputs(o, scene.source, model.name, result, names, runs, plot.get());
  return kOk;
}

}  // namespace

void add_bench_command(CLI::App& app, Command& command) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* sub = app.add_subcommand(
      "bench", "Work precision: error against an RK4 reference vs cost, per integrator and step size");
  // The help says the default as default_duration() computes it.
  add_scene_options(sub, o->scene, /*single_run=*/false,
                    "the scene's duration, at most " + csv_number(kMaxDefaultDuration) + " s and " +
                        csv_number(kMaxDefaultSmallSteps) + " x the smallest step, rounded down to a multiple of the largest");
  sub->add_option("--integrators", o->integrators, "Comma-separated lanes as compare takes them, without @STEP: NAME[:N], implicit_euler_fixed_point, course")->capture_default_str()->type_name("LIST");
  sub->add_option("--dts", o->dts,
                  "Comma-separated step sizes in s (numbers or fractions: 1/240), each dividing the duration "
                  "(default: the scene's dt x 0.25, 0.5, 1, 2, 4, 8)")
      ->type_name("LIST");
  sub->add_option("--tols", o->tols,
                  "Comma-separated tolerances (rtol = atol) an adaptive lane (bs3, dopri5, rkf78) runs at, where a\n"
                  "fixed-step lane runs at --dts (default 1e-3,1e-4,...,1e-8); its first trial step is the scene's dt")
      ->type_name("LIST");
  sub->add_option("--error", o->error,
                  "The error each run is judged by: time, the largest over up to 40 sample times every step lands on\n"
                  "(L-infinity in time), or end, at T alone; the CSV has both")
      ->capture_default_str()
      ->type_name("time|end");
  sub->add_option("--frame-dts", o->frame_dts,
                  "Steps implicit_euler also runs, one per video frame: numbers or fractions, or 'none' "
                  "(those that do not divide the duration are left out)")
      ->capture_default_str()
      ->type_name("LIST");
  sub->add_option("--csv", o->csv,
                  "Write one row per run: integrator,dt,steps,force_evals,...,rms_error,max_error,diverged,"
                  "...,unconverged_steps,wrong,wrong_at,wrong_reason,unresolved,tolerance,rejected_steps")
      ->type_name("FILE.csv");
  sub->add_option("--plot", o->plot, "Draw the work-precision diagram (needs python3-matplotlib)")
      ->type_name("FILE.png");
  sub->add_option("--summary", o->summary, "Write each run's cost and error as JSON (docs/summary.md)")
      ->type_name("FILE.json");
  sub->add_option("--vary", o->vary,
                  "The study once per value, each against its own reference, its lanes labelled 'rk4 (ks = 2e4)': KEY a\n"
                  "dotted scene path, a glob over the spring types or ks / kd, as compare --vary takes it")
      ->type_name("KEY=V1,V2,...");
  sub->add_option("--scale", o->scale,
                  "Cost against sheet size instead: each lane (NAME@STEP) at cloth.particles = [N, N] for each N,\n"
                  "the sheet's size and total mass fixed (the first N keeps the scene's particle_mass)")
      ->type_name("N1,N2,...");
  sub->add_option("--budget", o->budget,
                  "Substeps against iterations at equal cost instead: each iterative solver (default " +
                      std::string(kBudgetSolvers) + ")\nat every split s x k = N a frame, s steps of 1/(F s) with "
                      "k iterations each, against compare's reference (docs/cli.md)")
      ->type_name("N");
  sub->add_option("--fps", o->scene.fps,
                  "With --budget: the frame the budget fills, F frames per simulated second (default: the scene's "
                  "render.fps if it writes one, else " + csv_number(kBudgetDefaultFps) + ")")
      ->type_name("F");
  add_progress_options(sub);
  add_no_overwrite_option(sub);
  sub->add_option("--jobs", o->jobs, "Runs at once (default 0: one per core)");
  add_shard_option(sub, o->shard);
  sub->add_option("--reference-refinement", o->reference_refinement,
                  "Reference step = smallest step / N, then halved once more to check it (a scene with projected contacts)")
      ->capture_default_str()
      ->type_name("N");
  sub->add_option("--reference-tolerance", o->reference_tolerance,
                  "The adaptive reference's tolerance on a smooth scene, then 100x tighter to check it")
      ->capture_default_str()
      ->type_name("TOL");
  sub->add_flag("--no-reference-cache", o->no_reference_cache,
                "Compute the reference even when the cache holds it, and do not store it\n"
                "($XDG_CACHE_HOME/clothsim; `clothsim cache clear` empties it; docs/compare.md)");
  sub->callback([o, sub, &command] {
    // --budget's solvers by default, not compare's four (most of which take no iterations).
    if (!o->budget.empty() && sub->count("--integrators") == 0) o->integrators = kBudgetSolvers;
    command = [o] { return bench_command(*o); };
  });
}

}  // namespace clothsim::cli
