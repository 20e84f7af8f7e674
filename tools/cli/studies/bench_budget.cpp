#include "bench_budget.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <memory>

#include "clip/common/cli_common.h"
#include "clip/common/memory_budget.h"
#include "clip/studies/budget_plan.h"
#include "clip/studies/study_common.h"
#include "study/budget_study.h"
#include "study/reference.h"
#include "study/task_pool.h"

namespace clothsim::cli {
namespace {

using analysis::BudgetPoint;
using analysis::BudgetResult;

void print_table(const BudgetResult& r) {
  std::printf("%-22s %9s %10s %8s %11s %9s %12s %9s %10s %12s  %s\n", "solver", "s x k", "dt (s)", "steps",
              "iterations", "cpu (s)", "max err (m)", "at t (s)", "max strain", "E lost (J/s)", "status");
  for (const BudgetPoint& p : r.points) {
    char split[24], err[24] = "-", at[24] = "-";
    std::snprintf(split, sizeof split, "%d x %d", p.substeps, p.iterations);
    if (p.finished && !p.unresolved) std::snprintf(err, sizeof err, "%.4g", p.max_error), std::snprintf(at, sizeof at, "%.4g", p.max_error_t);
    std::printf("%-22s %9s %10.4g %8" PRId64 " %11" PRId64 " %9.3g %12s %9s %10.4g %12.4g  %s\n",
                analysis::solver_name(r.spec, p.solver).c_str(), split, p.dt, p.totals.steps,
                p.totals.solver_iterations + p.totals.newton_iterations,
                p.totals.cpu_seconds, err, at, p.max_strain, p.energy_lost_per_second,
                analysis::budget_status(p, r.spec.reference_margin).c_str());
  }
}

void print_reference(const BudgetResult& r) {
  const analysis::BudgetReference& ref = r.reference;
  if (ref.adaptive)
    std::printf("reference: adaptive dopri5 at %g, checked at %g: ", ref.tolerance, ref.tolerance / analysis::kCheckTightening);
  else
    std::printf("reference: rk4 at %g s, checked at %g s: ", ref.dt, 2 * ref.dt);
  if (std::isnan(ref.estimated_error)) std::printf("estimated error unknown (the check did not finish)");
  else std::printf("estimated error %.3g m (largest over the frames)", ref.estimated_error);
  std::printf("; largest strain %.4g, energy lost %.4g J/s; %" PRId64 " steps, %.3g s CPU\n", ref.max_strain,
              ref.energy_lost_per_second, ref.steps, ref.cpu_seconds);
  if (r.colliders_move)
    std::printf("a collider moves within T: energy lost includes the work it does, in every run as in the reference's\n");
}

}  // namespace

int bench_budget(const clip::BenchOptions& o) {
  clip::install_interrupt_handler();
  SceneDef scene = clip::load_scene_within(o.scene.path, o.scene.sets, o.scene.max_memory);
  clip::BudgetPlan plan = clip::plan_budget(o, scene);
  for (const std::string& why : plan.left_out) std::fprintf(stderr, "bench --budget: %s; left out\n", why.c_str());
  const std::unique_ptr<clip::PlotScript> plot = clip::check_study_outputs(o.scene.path, o.csv, "", o.plot, "plot_budget.py");
  const Model model = clip::build_budget_model(o, scene, plan);
  clip::fit_budget_reference(plan, model, scene);
  const analysis::BudgetSpec& spec = plan.spec;
  const std::size_t runs = analysis::budget_points(spec).size();
  std::printf("bench %s --budget %d: %zu solver%s x %zu splits s x k = %d at %g frames/s (%s), T = %g s (%.0f frame%s), "
              "on %d threads\n",
              model.name.c_str(), spec.budget, spec.solvers.size(), spec.solvers.size() == 1 ? "" : "s",
              runs / spec.solvers.size(), spec.budget, spec.fps, plan.fps_from.c_str(), spec.duration,
              std::round(spec.duration * spec.fps), std::round(spec.duration * spec.fps) == 1 ? "" : "s",
              analysis::resolve_jobs(o.jobs));
  std::fflush(stdout);

  clip::SharedProgress progress("bench " + model.name + " --budget", static_cast<long>(runs + 1), "runs");
  analysis::StudyHooks hooks;
  hooks.stop = [] { return clip::interrupted(); };
  hooks.progress = progress.hook();
  const BudgetResult r = analysis::budget_study(model, spec, hooks);
  progress.finish();
  print_table(r);
  if (r.reference.finished) print_reference(r);
  if (r.complete && r.reference.finished) {
    std::printf("verdicts (the least largest error among the splits that finished, not WRONG):\n");
    for (std::size_t i = 0; i < spec.solvers.size(); ++i) {
      std::printf("  %s\n", analysis::budget_verdict(r, i).text.c_str());
      if (spec.budget > 1) std::printf("    both ends side by side: %s\n", clip::budget_compare_command(o, plan, i).c_str());
    }
  }
  clip::write_budget_outputs(o, scene.source, model.name, plan, r, plot.get());
  return clip::kOk;
}

}  // namespace clothsim::cli
