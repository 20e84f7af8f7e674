// clothsim.bench: `clothsim bench` planned, run and written by the CLI's own code
// (clip/studies/bench_plan.h, bench_outputs.h), every option a keyword: the work-precision study,
// once per --vary value, or the --scale study; a DataFrame with the CSV's columns, and the same
// files when asked.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "study_binding.h"
#include "clip/studies/bench_outputs.h"
#include "clip/studies/bench_plan.h"
#include "clip/studies/budget_plan.h"
#include "study/budget_study.h"
#include "study/tables/budget_table.h"
#include "clip/studies/study_common.h"
#include "study/scale_study.h"
#include "study/work_precision.h"

namespace py = pybind11;

namespace clothsim::python {
namespace {

bool writes_files(const clip::BenchOptions& o) { return !o.csv.empty() || !o.summary.empty() || !o.plot.empty(); }

// One scene's study; with files asked for, a reference that did not converge raises
// RuntimeFailure after writing them, as the CLI exits 1.
py::object bench_one(const clip::BenchOptions& o, SceneDef& def, const std::vector<Lane>& lanes) {
  const analysis::WorkPrecisionSpec plan = clip::plan_bench(o, def, lanes);
  const std::unique_ptr<clip::PlotScript> plot =
      clip::check_study_outputs(o.scene.path, o.csv, o.summary, o.plot, "plot_work_precision.py");
  const clip::BenchModels models(o, def, lanes, plan);
  const clip::LaneNames& names = models.spec.lane_names;
  if (!o.shard.empty()) {  // the part's rows, journaled in CSV.shard-K-of-N/ as the CLI's
    interruptible([&](auto stop) {
      analysis::StudyHooks hooks;
      hooks.stop = stop;
      return clip::bench_shard(o, models.model, models.spec, names, hooks);
    });
    return shard_frame(o.csv, o.shard);
  }
  const analysis::WorkPrecisionResult r = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::work_precision(models.model, models.spec, hooks);
  });
  if (writes_files(o)) clip::write_bench_outputs(o, def.source, models.model.name, r, names, r.points.size(), plot.get());
  return data_frame(analysis::work_precision_table(r, names));
}

// --vary: the study once per value, each against its own reference, its rows labelled
// "rk4 (ks = 2e4)", one table.
py::object bench_values(const clip::BenchOptions& o, const SceneDef& def, const std::vector<Lane>& lanes) {
  std::vector<clip::ValueStudy> studies = clip::plan_values(o, def, lanes);
  const std::unique_ptr<clip::PlotScript> plot =
      clip::check_study_outputs(o.scene.path, o.csv, "", o.plot, "plot_work_precision.py");
  std::size_t runs = 0;
  std::string failure;  // the first value whose reference did not converge
  for (clip::ValueStudy& s : studies) {
    const clip::BenchModels models(o, s.scene, lanes, s.spec);
    runs += analysis::planned_points(models.spec).size();
    s.result = interruptible([&](auto stop) {
      analysis::StudyHooks hooks;
      hooks.stop = stop;
      return analysis::work_precision(models.model, models.spec, hooks);
    });
    if (!s.result.reference.converged && failure.empty()) failure = s.label + ": " + s.result.reference.failure;
  }
  if (writes_files(o)) clip::write_values_outputs(o, def, studies, runs, runs, failure, plot.get());
  return data_frame(clip::values_table(studies));
}

// --scale: each lane at each sheet size, its cost (no reference).
py::object bench_scale(const clip::BenchOptions& o) {
  const clip::ScalePlan scale = clip::plan_scale(o);
  const std::unique_ptr<clip::PlotScript> plot =
      clip::check_study_outputs(o.scene.path, o.csv, "", o.plot, "plot_scale.py");
  clip::check_scale_memory(o, scale);
  const std::vector<analysis::ScalePoint> points = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::scale_study(scale.spec, hooks, [](const analysis::ScalePoint&) {});
  });
  if (writes_files(o)) clip::write_scale_outputs(o, scale, points, plot.get());
  return csv_frame(clip::scale_csv_text(scale, points));
}

// budget=N (--budget): the substeps-iterations grid, its verdicts in the DataFrame's
// attrs["verdicts"] (one line per solver, as the CLI prints them).
py::object bench_budget(const clip::BenchOptions& o, SceneDef& def) {
  clip::BudgetPlan plan = clip::plan_budget(o, def);
  for (const std::string& why : plan.left_out)
    PyErr_WarnEx(PyExc_UserWarning, ("bench --budget: " + why + "; left out").c_str(), 1);
  const std::unique_ptr<clip::PlotScript> plot =
      clip::check_study_outputs(o.scene.path, o.csv, "", o.plot, "plot_budget.py");
  const Model model = clip::build_budget_model(o, def, plan);
  clip::fit_budget_reference(plan, model, def);
  const analysis::BudgetResult r = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::budget_study(model, plan.spec, hooks);
  });
  if (writes_files(o)) clip::write_budget_outputs(o, def.source, model.name, plan, r, plot.get());
  if (!r.reference.finished) throw clip::RuntimeFailure(def.source + ": " + r.reference.failure + "; nothing measured");
  py::object frame = data_frame(analysis::budget_table(r, clip::budget_lane_spellings(plan, r)));
  py::list verdicts;
  for (std::size_t i = 0; i < plan.spec.solvers.size(); ++i) verdicts.append(analysis::budget_verdict(r, i).text);
  frame.attr("attrs")["verdicts"] = verdicts;
  return frame;
}

py::object bench(const Scene& scene, const py::object& integrators, const py::object& dts,
                 const std::optional<double>& duration, const py::object& frame_dts,
                 const std::optional<int>& reference_refinement, const std::optional<double>& reference_tolerance,
                 int jobs, const std::string& csv, const std::string& summary, const std::string& plot,
                 const std::string& vary, const py::object& scale, const std::string& shard,
                 const py::object& max_memory, const py::object& tols, const std::string& error,
                 const py::object& budget, const std::optional<double>& fps) {
  clip::BenchOptions o;  // the CLI's defaults where a keyword is None
  o.scene = scene_options(scene, duration, max_memory);
  if (!budget.is_none()) o.budget = option_text(budget), o.integrators = clip::kBudgetSolvers;
  if (fps) o.scene.fps = *fps;
  if (!integrators.is_none()) o.integrators = option_text(integrators);
  if (!dts.is_none()) o.dts = option_text(dts);
  if (!tols.is_none()) o.tols = option_text(tols);
  o.error = error;
  o.frame_dts = frame_dts_text(frame_dts, o.frame_dts);
  if (reference_refinement) o.reference_refinement = *reference_refinement;
  if (reference_tolerance) o.reference_tolerance = *reference_tolerance;
  o.jobs = jobs;
  o.csv = csv, o.summary = summary, o.plot = plot, o.vary = vary, o.shard = shard;
  if (!scale.is_none()) o.scale = option_text(scale);
  if (!o.scale.empty()) return bench_scale(o);
  SceneDef def = scene.def;
  if (!o.budget.empty()) return bench_budget(o, def);
  if (fps) throw clip::UsageError("--fps: the frame of --budget; give budget=N with it");
  const std::vector<Lane> lanes = clip::bench_lanes(o, def);
  if (!o.vary.empty()) return bench_values(o, def, lanes);
  return bench_one(o, def, lanes);
}

}  // namespace

void bind_bench(py::module_& m) {
  m.def("bench", &bench, py::arg("scene"), py::arg("integrators") = py::none(), py::arg("dts") = py::none(),
        py::arg("duration") = py::none(), py::arg("frame_dts") = py::none(),
        py::arg("reference_refinement") = py::none(), py::arg("reference_tolerance") = py::none(),
        py::arg("jobs") = 0, py::arg("csv") = "", py::arg("summary") = "", py::arg("plot") = "", py::arg("vary") = "",
        py::arg("scale") = py::none(), py::arg("shard") = "", py::arg("max_memory") = py::none(),
        py::arg("tols") = py::none(), py::arg("error") = "time", py::arg("budget") = py::none(),
        py::arg("fps") = py::none(),
        "bench(scene, integrators=None, dts=None, duration=None, frame_dts=None, reference_refinement=None,\n"
        "      reference_tolerance=None, jobs=0, csv='', summary='', plot='', vary='', scale=None, shard='',\n"
        "      max_memory=None, tols=None, error='time', budget=None, fps=None)\n"
        "    -> pandas.DataFrame\n\n"
        "`clothsim bench SCENE` with its options as keywords: every lane at every step over T, its error at\n"
        "T against the reference and its cost. A keyword left None takes the CLI's default (compare's\n"
        "four lanes, the scene's dt x 0.25..8, T = min(scene, 0.5 s, 8000 x the smallest step) rounded to\n"
        "the largest, implicit_euler also at one step per frame), so bench(scene) is `clothsim bench\n"
        "SCENE`'s table. Columns as bench --csv. Lists may be Python lists.\n"
        "tols=[1e-4, 1e-6, ...] (--tols): the tolerances an adaptive lane (bs3, dopri5, rkf78) runs at, one\n"
        "  row each (column tolerance), beside the fixed-step lanes' steps (default 1e-3 .. 1e-8).\n"
        "error='time' (--error): each run judged by its largest error over the sample times (L-infinity in\n"
        "  time), or 'end', at T alone; the table has both (rms_error_at_end, rms_error_over_time).\n"
        "vary='KEY=V1,V2,...' (--vary): the study once per value, each against its own reference, its rows\n"
        "  labelled 'rk4 (ks = 2e4)' (KEY a dotted path, a glob or ks / kd); one table.\n"
        "scale=[N1, N2, ...] (--scale): cost against sheet size instead, each lane NAME@STEP at\n"
        "  cloth.particles = [N, N]; columns as bench --scale --csv (lane, side, ..., cpu_seconds, peak_rss_mb).\n"
        "Files, as the CLI writes them (atomically; none is written if Ctrl-C stops the study):\n"
        "  csv='F.csv' (--csv), summary='F.json' (--summary, docs/summary.md), plot='F.png' (--plot:\n"
        "  python3-matplotlib). With a file asked for, a reference that did not converge raises\n"
        "  clothsim.RuntimeFailure after writing the CSV, as the CLI exits 1; without, the rows return.\n"
        "shard='K/N' (or 'auto' in a Slurm array task): part K of N of the runs, journaled in\n"
        "  csv + '.shard-K-of-N/' for `clothsim merge` (needs csv=; no summary or plot); returns the part's\n"
        "  rows; a rerun runs only what the part does not hold yet (docs/cluster.md).\n"
        "budget=N (--budget): substeps against iterations at equal cost instead: each iterative solver\n"
        "  (integrators=, default xpbd,vbd,projective_dynamics,implicit_euler) at every split s x k = N a\n"
        "  frame of 1/fps s (fps=: --fps, default the scene's render.fps if written, else 60); columns as\n"
        "  bench --budget --csv, the verdicts in the DataFrame's attrs['verdicts'] (docs/cli.md).\n"
        "max_memory='4G' (--max-memory): refuse a study whose runs would need more (default: half the RAM).\n"
        "Runs with the GIL released; Ctrl-C raises KeyboardInterrupt; bad options raise\n"
        "clothsim.UsageError (a ValueError) with the CLI's one-line message.");
}

}  // namespace clothsim::python
