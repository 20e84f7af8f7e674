#include "budget_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "clip/common/cli_common.h"
#include "clip/common/memory_budget.h"
#include "clip/frames/picture_options.h"
#include "scene/build_model.h"
#include "scene/memory_estimate.h"
#include "scene/run_bounds.h"
#include "study/tables/budget_table.h"
#include "study/task_pool.h"

namespace clothsim::clip {
namespace {

// A step of one in F s a frame, as compare takes it: "1/1800" where F s is whole.
std::string step_text(double fps, int substeps) {
  const double per_second = fps * substeps;
  if (std::abs(per_second - std::round(per_second)) <= 1e-9 * per_second)
    return "1/" + number_text(std::round(per_second));
  return number_text(1.0 / per_second);
}

Lane split_lane(const Lane& solver, double fps, int substeps, int iterations) {
  Lane l = solver;
  l.dt = 1.0 / (fps * substeps);
  l.step_text = step_text(fps, substeps);
  l.step_from = StepFrom::Written;
  l.iterations = iterations;
  return l;
}

// Options that belong to bench's other studies: refused beside --budget rather than ignored.
void refuse_other_studies(const BenchOptions& o) {
  const auto refuse = [](const std::string& option, const std::string& why) {
    throw UsageError("--budget: " + option + " " + why);
  };
  if (o.dts) refuse("--dts", "sweeps steps; the budget sets each step to 1 / (F s): give one or the other");
  if (!o.vary.empty()) refuse("--vary", "runs the step sweep once per value; give one study at a time");
  if (!o.scale.empty()) refuse("--scale", "is the sheet-size study; give one study at a time");
  if (!o.shard.empty()) refuse("--shard", "splits the step sweep's runs; the budget grid runs in one process");
  if (o.tols) refuse("--tols", "sweeps an adaptive lane's tolerances; the budget's lanes are iterative solvers");
  if (o.error != "time") refuse("--error", "chooses the step sweep's measure; the budget's is the largest over every frame");
  if (!o.summary.empty()) refuse("--summary", "is the step sweep's JSON; the budget writes --csv");
  if (o.frame_dts != kDefaultFrameDts) refuse("--frame-dts", "adds implicit_euler's frame steps to the step sweep");
  const BenchOptions defaults;
  if (o.reference_refinement != defaults.reference_refinement || o.reference_tolerance != defaults.reference_tolerance)
    refuse(o.reference_refinement != defaults.reference_refinement ? "--reference-refinement" : "--reference-tolerance",
           "sets the step sweep's reference; the budget's is compare's (docs/cli.md)");
}

}  // namespace

BudgetPlan plan_budget(const BenchOptions& o, const SceneDef& scene) {
  BudgetPlan plan;
  analysis::BudgetSpec& spec = plan.spec;
  spec.budget = parse_iteration_option(o.budget, "--budget");
  refuse_other_studies(o);
  const bool default_list = o.integrators == kBudgetSolvers;
  std::vector<Lane> lanes = parse_study_lanes(o.integrators, "--budget sets each step to 1 / (F s); drop @STEP");
  follow_scene_solver(lanes, scene.implicit);
  for (const Lane& l : lanes) {
    const std::string item = "--integrators: '" + l.stepless_spelling() + "': ";  // as parse_study_lanes says an item
    if (integrator_info(l.kind).iterations == IterationControl::None)
      throw UsageError(item + "not an iterative solver; --budget splits the iterations of xpbd, vbd, "
                              "projective_dynamics or implicit_euler (its Newton cap)");
    if ((l.iterations > 0 && !l.fixed_point) || l.tolerance > 0.0)
      throw UsageError(item + "--budget sets the iterations of each split (N / s); drop :N and :tol=");
    const std::string refused = scene.collision.model == ContactModel::Barrier ? barrier_refusal(l.kind) : "";
    if (!refused.empty() && default_list) {
      plan.left_out.push_back(refused);
      continue;
    }
    if (!refused.empty()) throw UsageError("--integrators: collision.model: barrier: " + refused);
    plan.lanes.push_back(l);
    plan.lanes.back().iterations = 0;
    spec.solvers.push_back(l.kind);
    spec.solver_names.push_back(l.stepless_spelling());
  }
  if (spec.solvers.empty()) throw UsageError("--integrators: no solver of the list runs on this scene");

  // The frame: --fps, else the scene's render.fps if it writes one, else Macklin's 60.
  spec.fps = o.scene.fps ? *o.scene.fps : scene.render.fps_given ? scene.render.fps : kBudgetDefaultFps;
  plan.fps_from = o.scene.fps ? "--fps" : scene.render.fps_given ? "the scene's render.fps" : "the default";
  if (!(spec.fps > 0.0) || !std::isfinite(spec.fps) || spec.fps > RenderDef::kMaxFps)
    throw UsageError("--fps: must be > 0 and <= " + number_text(RenderDef::kMaxFps) + " frames per second, got " +
                     number_text(spec.fps));
  spec.duration = o.scene.duration ? *o.scene.duration : scene.duration;
  const std::string whence = o.scene.duration ? "--duration" : scene.source + ": duration";
  const double frames = spec.duration * spec.fps;
  if (!(spec.duration > 0.0) || !std::isfinite(spec.duration) || std::round(frames) < 1.0 ||
      std::abs(frames - std::round(frames)) > 1e-9 * std::round(frames))
    throw UsageError(whence + ": " + number_text(spec.duration) + " s is not a whole number of frames at " +
                     number_text(spec.fps) + " frames/s (" + plan.fps_from + "); give a --duration that is a multiple of 1/" +
                     number_text(spec.fps) + " s");
  const std::string too_long = run_bounds_problem(spec.duration, 1.0 / (spec.fps * spec.budget), spec.fps);
  if (!too_long.empty()) throw UsageError("--budget: " + too_long);
  if (o.jobs < 0) throw UsageError("--jobs: must be >= 0 (0: one per core)");
  spec.jobs = o.jobs;
  return plan;
}

Model build_budget_model(const BenchOptions& o, SceneDef& scene, const BudgetPlan& plan) {
  scene.duration = std::max(scene.duration, plan.spec.duration);
  MemoryBudget budget;  // bench's (check_bench_memory), and the reference's frames
  budget.add("model", model_bytes(scene));
  double dearest = 0.0;
  for (IntegratorKind k : plan.spec.solvers) dearest = std::max(dearest, run_bytes(scene, k));
  const int threads = analysis::resolve_jobs(o.jobs);
  budget.add(std::to_string(threads) + " runs at once", threads * dearest);
  // Positions (3 doubles) and inverse masses (1) of every body at every frame, twice while the
  // RK4 reference and its check both keep theirs (budget_study.h).
  const double bodies = static_cast<double>(scene.cloth.nx) * scene.cloth.ny + scene.spheres.size();
  budget.add("reference frames", 2.0 * (std::round(plan.spec.duration * plan.spec.fps) + 1) * bodies * 4 * sizeof(double));
  budget.check(scene.source, o.scene.max_memory);
  return build_model(scene);
}

void fit_budget_reference(BudgetPlan& plan, const Model& model, const SceneDef& scene) {
  analysis::BudgetSpec& spec = plan.spec;
  const std::vector<Lane> smallest = {split_lane(plan.lanes.front(), spec.fps, spec.budget, 1)};
  PictureLook look;  // compare's default reference for a lane of the smallest step
  look.reference = parse_reference("", smallest);
  look.reference_is_default = true;
  fit_reference_to_model(look, model, scene, smallest);
  spec.reference_dt = look.reference->dt;
  if (look.reference_tolerance > 0.0) spec.reference_tolerance = look.reference_tolerance;
  spec.solver_settings = [lanes = plan.lanes](const Model& base, std::size_t i, int k) {
    Lane l = lanes[i];
    l.iterations = k;
    return lane_settings(base, l);
  };
}

std::vector<std::string> budget_lane_spellings(const BudgetPlan& plan, const analysis::BudgetResult& r) {
  std::vector<std::string> out;
  for (const analysis::BudgetPoint& p : r.points)
    out.push_back(split_lane(plan.lanes[p.solver], r.spec.fps, p.substeps, p.iterations).spelling());
  return out;
}

std::string budget_compare_command(const BenchOptions& o, const BudgetPlan& plan, std::size_t solver) {
  const analysis::BudgetSpec& spec = plan.spec;
  const auto word = [](const std::string& w) {  // quoted for a POSIX shell where it needs it
    if (w.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789@%+=:,./_-") == std::string::npos)
      return w;
    std::string q = "'";
    for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  };
  const Lane& l = plan.lanes[solver];
  std::string cmd = "clothsim compare " + word(o.scene.path) + " --integrators " +
                    split_lane(l, spec.fps, 1, spec.budget).spelling() + "," +
                    split_lane(l, spec.fps, spec.budget, 1).spelling();
  for (const std::string& set : o.scene.sets) cmd += " --set " + word(set);
  if (o.scene.duration) cmd += " --duration " + number_text(*o.scene.duration);
  if (o.scene.fps) cmd += " --fps " + number_text(*o.scene.fps);
  return cmd + " --video " + word("budget_" + l.stepless_spelling() + ".mp4");
}

std::string budget_plot_title(const std::string& name, const analysis::BudgetResult& r) {
  char text[200];
  std::snprintf(text, sizeof text, "%s, N = %d iterations a frame at %g frames/s, T = %g s; reference error %.2g m",
                name.c_str(), r.spec.budget, r.spec.fps, r.spec.duration, r.reference.estimated_error);
  return text;
}

void write_budget_outputs(const BenchOptions& o, const std::string& source, const std::string& name,
                          const BudgetPlan& plan, const analysis::BudgetResult& r, const PlotScript* plot) {
  const std::vector<std::string> lanes = budget_lane_spellings(plan, r);
  const auto write_to = [&](const std::string& path) {
    AtomicFile file(path);
    std::fputs(analysis::budget_table(r, lanes).text().c_str(), file.stream());
    file.commit();
  };
  if (!o.csv.empty() && r.reference.finished) write_to(o.csv);
  const std::size_t planned = analysis::budget_points(r.spec).size();
  if (interrupted() || !r.complete)
    throw RuntimeFailure(study_interrupted_message(r.points.size(), planned, "runs",
                                                   {r.reference.finished ? o.csv : ""}, o.plot));
  if (!r.reference.finished) throw RuntimeFailure(source + ": " + r.reference.failure + "; nothing measured");
  if (plot) plot->draw_from_csv(o.csv, write_to, {"--title", budget_plot_title(name, r)}, {o.csv});
}

}  // namespace clothsim::clip
