// clothsim.stability and .converge: the CLI's studies planned, run and written by the CLI's own
// code (clip/studies: *_plan.h, *_outputs.h), each as a pandas DataFrame with the CSV's columns,
// and the same files when asked; and what the study bindings share (study_binding.h).
#include "study_binding.h"

#include <pybind11/stl.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clip/studies/converge_outputs.h"
#include "clip/studies/converge_plan.h"
#include "clip/studies/stability_outputs.h"
#include "clip/studies/stability_plan.h"
#include "clip/studies/study_common.h"
#include "clip/merge/study_merge.h"
#include "clip/studies/study_shard.h"
#include "scene/build_model.h"
#include "study/convergence.h"
#include "study/stability.h"

namespace py = pybind11;

namespace clothsim::python {

py::object data_frame(const analysis::CsvTable& table) { return csv_frame(table.text()); }

py::object csv_frame(const std::string& text) {
  const py::object buffer = py::module_::import("io").attr("StringIO")(text);
  py::object frame = py::module_::import("pandas").attr("read_csv")(buffer, py::arg("float_precision") = "round_trip");
  // The verdicts the CSV writes as 0 / 1 are booleans to a DataFrame's reader (df[df.diverged]).
  for (const char* column : {"diverged", "wrong", "unresolved", "converged", "frame_step", "finished"}) {
    if (!py::bool_(frame.attr("columns").attr("__contains__")(column))) continue;
    py::object values = frame[column];
    if (py::bool_(values.attr("isin")(py::make_tuple(0, 1)).attr("all")())) frame[column] = values.attr("astype")("bool");
  }
  return frame;
}

py::object shard_frame(const std::string& csv, const std::string& shard) {
  const std::string dir = clip::shard_dir(csv, clip::parse_shard_option(shard));
  return csv_frame(clip::part_csv(clip::read_part(dir)));
}

clip::SceneOptions scene_options(const Scene& scene, const std::optional<double>& duration,
                                 const py::object& max_memory) {
  clip::SceneOptions o;
  o.max_memory = max_memory_keyword(max_memory);
  o.path = scene.def.source;
  o.sets = scene.overrides;
  if (scene.dt) {
    char text[40];
    std::snprintf(text, sizeof text, "dt=%.17g", *scene.dt);
    o.sets.push_back(text);
  }
  o.duration = duration ? duration : scene.duration;
  return o;
}

std::string frame_dts_text(const py::object& frame_dts, const std::string& fallback) {
  if (frame_dts.is_none()) return fallback;
  const std::string text = option_text(frame_dts);
  return text.empty() ? "none" : text;
}

namespace {

py::object converge(const Scene& scene, const py::object& dt, const py::object& integrators,
                    const std::optional<int>& states, const std::optional<int>& max_iterations, const std::string& csv,
                    const std::string& summary, const std::string& plot, const std::string& shard,
                    const std::optional<double>& duration, const py::object& max_memory) {
  clip::ConvergeOptions o;  // the CLI's defaults where a keyword is None
  o.scene = scene_options(scene, duration, max_memory);
  if (!dt.is_none()) o.dt = option_text(dt);
  if (!integrators.is_none()) o.integrators = option_text(integrators);
  if (states) o.states = std::to_string(*states);
  if (max_iterations) o.max_iterations = std::to_string(*max_iterations);
  o.csv = csv, o.summary = summary, o.plot = plot, o.shard = shard;
  const ConvergenceSpec spec = clip::plan_converge(o);
  const SceneDef def = clip::load_scene_with_options(o.scene);  // as the CLI reads it: duration=, max_memory=
  const Model model = build_model(def);
  if (!o.shard.empty()) {  // the part's rows, journaled in CSV.shard-K-of-N/ as the CLI's
    clip::check_study_outputs(o.scene.path, o.csv, o.summary, "", "");
    interruptible([&](auto stop) {
      analysis::StudyHooks hooks;
      hooks.stop = stop;
      return clip::converge_shard(o, model, spec, hooks);
    });
    return shard_frame(o.csv, o.shard);
  }
  const std::unique_ptr<clip::PlotScript> plotter =
      clip::check_study_outputs(o.scene.path, o.csv, o.summary, o.plot, "plot_convergence.py");
  const std::vector<ConvergencePoint> points = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return convergence_study(model, spec, hooks);
  });
  clip::write_converge_outputs(o, def.source, model, spec, points, plotter.get());
  return data_frame(analysis::convergence_table(points, model.name));
}

py::object stability(const Scene& scene, const py::object& integrators, const std::string& param,
                     const py::object& values, const std::optional<double>& duration,
                     const std::optional<double>& min_dt, const std::optional<double>& max_dt,
                     const std::optional<double>& precision, const std::optional<double>& energy_factor,
                     const std::optional<double>& max_strain, const py::object& frame_dts, int jobs,
                     const std::string& csv, const std::string& summary, const std::string& plot,
                     const std::string& shard, const py::object& max_memory) {
  clip::StabilityOptions o;  // the CLI's defaults where a keyword is None
  o.scene = scene_options(scene, duration, max_memory);
  if (!integrators.is_none()) o.integrators = option_text(integrators);
  o.param = param;
  if (!values.is_none()) o.values = option_text(values);
  o.min_dt = min_dt;
  o.max_dt = max_dt;
  if (precision) o.precision = *precision;
  if (energy_factor) o.energy_factor = *energy_factor;
  if (max_strain) o.max_strain = *max_strain;
  o.frame_dts = frame_dts_text(frame_dts, o.frame_dts);
  o.jobs = jobs;
  o.csv = csv, o.summary = summary, o.plot = plot, o.shard = shard;
  clip::StabilityStudy study = clip::plan_stability(o, scene.def);
  const std::unique_ptr<clip::PlotScript> plotter =
      clip::check_study_outputs(o.scene.path, o.csv, o.summary, o.plot, "plot_stability.py");
  const std::vector<analysis::StabilityCase> cases = study.refs();
  if (!o.shard.empty()) {  // the part's rows, journaled in CSV.shard-K-of-N/ as the CLI's
    interruptible([&](auto stop) {
      analysis::StudyHooks hooks;
      hooks.stop = stop;
      return clip::stability_shard(o, scene.def.name, cases, study.spec, study.names, hooks);
    });
    return shard_frame(o.csv, o.shard);
  }
  const std::vector<analysis::StabilityLimit> limits = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::stability_sweep(cases, study.spec, hooks);
  });
  clip::write_stability_outputs(o, scene.def, limits, study, plotter.get());
  return data_frame(analysis::stability_table(limits, study.spec, param, study.names));
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def("stability", &stability, py::arg("scene"), py::arg("integrators") = py::none(),
        py::arg("param") = "cloth.springs.structural.stiffness", py::arg("values") = py::none(),
        py::arg("duration") = py::none(), py::arg("min_dt") = py::none(), py::arg("max_dt") = py::none(),
        py::arg("precision") = py::none(), py::arg("energy_factor") = py::none(), py::arg("max_strain") = py::none(),
        py::arg("frame_dts") = py::none(), py::arg("jobs") = 0, py::arg("csv") = "", py::arg("summary") = "",
        py::arg("plot") = "", py::arg("shard") = "", py::arg("max_memory") = py::none(),
        "stability(scene, integrators=None, param='cloth.springs.structural.stiffness', values=None,\n"
        "          duration=None, min_dt=None, max_dt=None, precision=None, energy_factor=None,\n"
        "          max_strain=None, frame_dts=None, jobs=0, csv='', summary='', plot='', shard='',\n"
        "          max_memory=None)\n"
        "    -> pandas.DataFrame\n\n"
        "`clothsim stability SCENE` with its options as keywords: for each value of the scene key `param`\n"
        "(a path, a glob or ks / kd), each lane's largest stable step over T, bracketed to `precision`.\n"
        "A keyword left None takes the CLI's default (compare's four lanes, the scene's value x 1..1e4,\n"
        "T = min(scene, 0.2 s), ...), so stability(scene) is `clothsim stability SCENE`'s table. Lists may\n"
        "be Python lists; frame_dts=[] is 'none'. Columns as stability --csv.\n"
        "Files, as the CLI writes them (atomically; none is written if Ctrl-C stops the study):\n"
        "  csv='F.csv' (--csv), summary='F.json' (--summary, docs/summary.md), plot='F.png' (--plot,\n"
        "  drawn by tools/plot_stability.py: python3-matplotlib).\n"
        "shard='K/N' (or 'auto' in a Slurm array task): part K of N of the searches, journaled in\n"
        "  csv + '.shard-K-of-N/' for `clothsim merge` (needs csv=; no summary or plot); returns the part's\n"
        "  rows; a rerun runs only what the part does not hold yet (docs/cluster.md).\n"
        "max_memory='4G' (--max-memory): refuse a sweep whose runs would need more (default: half the RAM).\n"
        "GIL released; Ctrl-C: KeyboardInterrupt; bad options raise clothsim.UsageError (a ValueError).");
  bind_bench(m);
  m.def("converge", &converge, py::arg("scene"), py::arg("dt") = py::none(), py::arg("integrators") = py::none(),
        py::arg("states") = py::none(), py::arg("max_iterations") = py::none(), py::arg("csv") = "",
        py::arg("summary") = "", py::arg("plot") = "", py::arg("shard") = "", py::arg("duration") = py::none(),
        py::arg("max_memory") = py::none(),
        "converge(scene, dt=None, integrators=None, states=None, max_iterations=None, csv='', summary='',\n"
        "         plot='', shard='', duration=None, max_memory=None) -> pandas.DataFrame\n\n"
        "`clothsim converge SCENE` with its options as keywords (None: the CLI's default, dt=1/60,\n"
        "integrators xpbd, projective_dynamics, vbd, implicit_euler, states=5, max_iterations=50): from\n"
        "`states` states along a converged implicit_euler run, one step of each method with\n"
        "1..max_iterations iterations, its distance from the converged backward-Euler step. Columns as\n"
        "converge --csv: scene, method, state, t, iterations, rms_distance, max_distance, gradient_norm,\n"
        "cpu_seconds, wrong.\n"
        "Files, as the CLI writes them (atomically; none is written if Ctrl-C stops the study):\n"
        "  csv='F.csv' (--csv), summary='F.json' (--summary: mean distance and CPU per method and\n"
        "  iteration count), plot='F.png' (--plot, tools/plot_convergence.py: python3-matplotlib).\n"
        "shard='K/N' or 'auto': part K of N of the (state, method) sweeps, journaled in csv +\n"
        "  '.shard-K-of-N/' for `clothsim merge` (needs csv=; no summary or plot); returns the part's rows.\n"
        "duration= (--duration): the converged run the states are taken along (default: the scene's);\n"
        "max_memory='4G' (--max-memory).\n"
        "Runs with the GIL released; Ctrl-C raises KeyboardInterrupt; bad options raise\n"
        "clothsim.UsageError (a ValueError).");
}

}  // namespace clothsim::python
