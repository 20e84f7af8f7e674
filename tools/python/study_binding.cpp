// clothsim.bench, .stability and .converge: the CLI's studies planned by the CLI's own code
// (clip/studies/*_plan.h: the same defaults, lanes and refusals), each as a pandas DataFrame
// with the CSV's columns, and the same CSV when asked.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <functional>
#include <future>
#include <string>
#include <vector>

#include "scene_binding.h"
#include "clip/studies/bench_plan.h"
#include "clip/studies/converge_plan.h"
#include "clip/studies/stability_plan.h"
#include "render/output_file.h"
#include "study/convergence.h"
#include "study/tables/csv_tables.h"
#include "study/stability.h"
#include "study/work_precision.h"

namespace py = pybind11;

namespace clothsim::python {
namespace {

// Runs `work` on its own thread with the GIL released, checking Python's signals every 0.1 s
// from this (the main) thread: a KeyboardInterrupt stops the work through `stop` and is raised.
template <typename Work>
auto interruptible(Work work) {
  std::atomic<bool> stop{false};
  auto result = std::async(std::launch::async, [&] { return work([&stop] { return stop.load(); }); });
  for (;;) {
    {
      py::gil_scoped_release release;
      if (result.wait_for(std::chrono::milliseconds(100)) == std::future_status::ready) break;
    }
    if (PyErr_CheckSignals() != 0) {
      stop = true;
      {
        py::gil_scoped_release release;
        result.wait();
      }
      throw py::error_already_set();
    }
  }
  return result.get();
}

// `table` as the CLI's --csv writes it (study/tables/csv_tables.h: the same text), whole or not at all.
void write_csv(const std::string& path, const analysis::CsvTable& table) {
  const std::string text = table.text();
  OutputFile file(path);
  if (!write_all(file.fd(), text.data(), text.size())) throw OutputFileError("cannot write " + path);
  file.commit();
}

// A study's table (study/tables/csv_tables.h, the one the CLI's --csv writes) as a DataFrame: its
// columns in order, numbers as floats, whole numbers as ints, texts as str.
py::object data_frame(const analysis::CsvTable& table) {
  py::dict data;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    py::list values;
    for (const std::vector<analysis::CsvCell>& row : table.rows) {
      const analysis::CsvCell& cell = row[c];
      switch (cell.kind) {
        case analysis::CsvCell::Kind::Number: values.append(py::float_(cell.number)); break;
        case analysis::CsvCell::Kind::Integer: values.append(py::int_(cell.integer)); break;
        case analysis::CsvCell::Kind::Text: values.append(py::str(cell.text)); break;
      }
    }
    data[py::str(table.columns[c])] = values;
  }
  return py::module_::import("pandas").attr("DataFrame")(data);
}

// The scene's file and --set strings as the CLI's options (its step as --set dt: a study
// reloads the scene for each swept value), and its duration= as --duration where `duration`
// is not given.
clip::SceneOptions scene_options(const Scene& scene, const std::optional<double>& duration) {
  clip::SceneOptions o;
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

// frame_dts=: None (the CLI's default), [] or "none" (none), numbers or fractions.
std::string frame_dts_text(const py::object& frame_dts, const std::string& fallback) {
  if (frame_dts.is_none()) return fallback;
  const std::string text = option_text(frame_dts);
  return text.empty() ? "none" : text;
}

py::object converge(const Scene& scene, const py::object& dt, const py::object& integrators,
                    const std::optional<int>& states, const std::optional<int>& max_iterations, const std::string& csv) {
  clip::ConvergeOptions o;  // the CLI's defaults where a keyword is None
  o.scene = scene_options(scene, std::nullopt);
  if (!dt.is_none()) o.dt = option_text(dt);
  if (!integrators.is_none()) o.integrators = option_text(integrators);
  if (states) o.states = std::to_string(*states);
  if (max_iterations) o.max_iterations = std::to_string(*max_iterations);
  const ConvergenceSpec spec = clip::plan_converge(o);
  const Model& model = *scene.model;
  const std::vector<ConvergencePoint> points = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return convergence_study(model, spec, hooks);
  });
  const analysis::CsvTable table = analysis::convergence_table(points, model.name);
  py::object frame = data_frame(table);
  if (!csv.empty()) write_csv(csv, table);
  return frame;
}

py::object bench(const Scene& scene, const py::object& integrators, const py::object& dts,
                 const std::optional<double>& duration, const py::object& frame_dts,
                 const std::optional<int>& reference_refinement, const std::optional<double>& reference_tolerance,
                 int jobs, const std::string& csv) {
  clip::BenchOptions o;  // the CLI's defaults where a keyword is None
  o.scene = scene_options(scene, duration);
  if (!integrators.is_none()) o.integrators = option_text(integrators);
  if (!dts.is_none()) o.dts = option_text(dts);
  o.frame_dts = frame_dts_text(frame_dts, o.frame_dts);
  if (reference_refinement) o.reference_refinement = *reference_refinement;
  if (reference_tolerance) o.reference_tolerance = *reference_tolerance;
  o.jobs = jobs;
  SceneDef def = scene.def;
  const std::vector<clip::LaneSpec> lanes = clip::bench_lanes(o, def);
  analysis::WorkPrecisionSpec spec = clip::plan_bench(o, def, lanes);
  const Model model = clip::build_bench_model(o, def, lanes, spec);
  std::vector<std::optional<Model>> lane_storage;
  clip::attach_lane_models(model, lanes, lane_storage, spec);
  const analysis::WorkPrecisionResult r = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::work_precision(model, spec, hooks);
  });
  const analysis::CsvTable table = analysis::work_precision_table(r, spec.lane_names);
  py::object frame = data_frame(table);
  if (!csv.empty()) write_csv(csv, table);
  return frame;
}

py::object stability(const Scene& scene, const py::object& integrators, const std::string& param,
                     const py::object& values, const std::optional<double>& duration,
                     const std::optional<double>& min_dt, const std::optional<double>& max_dt,
                     const std::optional<double>& precision, const std::optional<double>& energy_factor,
                     const std::optional<double>& max_strain, const py::object& frame_dts, int jobs,
                     const std::string& csv) {
  clip::StabilityOptions o;  // the CLI's defaults where a keyword is None
  o.scene = scene_options(scene, duration);
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
  clip::StabilityStudy study = clip::plan_stability(o, scene.def);
  const std::vector<analysis::StabilityCase> cases = study.refs();
  const std::vector<analysis::StabilityLimit> limits = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::stability_sweep(cases, study.spec, hooks);
  });
  const analysis::CsvTable table = analysis::stability_table(limits, study.spec, param, study.names);
  py::object frame = data_frame(table);
  if (!csv.empty()) write_csv(csv, table);
  return frame;
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def("stability", &stability, py::arg("scene"), py::arg("integrators") = py::none(),
        py::arg("param") = "cloth.springs.structural.stiffness", py::arg("values") = py::none(),
        py::arg("duration") = py::none(), py::arg("min_dt") = py::none(), py::arg("max_dt") = py::none(),
        py::arg("precision") = py::none(), py::arg("energy_factor") = py::none(), py::arg("max_strain") = py::none(),
        py::arg("frame_dts") = py::none(), py::arg("jobs") = 0, py::arg("csv") = "",
        "stability(scene, integrators=None, param='cloth.springs.structural.stiffness', values=None,\n"
        "          duration=None, min_dt=None, max_dt=None, precision=None, energy_factor=None,\n"
        "          max_strain=None, frame_dts=None, jobs=0, csv='') -> pandas.DataFrame\n\n"
        "`clothsim stability SCENE` with its options as keywords: for each value of the scene key `param`\n"
        "(a path, a glob or ks / kd), each lane's largest stable step over T, bracketed to `precision`.\n"
        "A keyword left None takes the CLI's default (compare's four lanes, the scene's value x 1..1e4,\n"
        "T = min(scene, 0.2 s), ...), so stability(scene) is `clothsim stability SCENE`'s table. Lists may\n"
        "be Python lists; frame_dts=[] is 'none'. Columns as stability --csv; `csv` writes that file too.\n"
        "GIL released; Ctrl-C: KeyboardInterrupt; bad options raise clothsim.UsageError (a ValueError).");
  m.def("bench", &bench, py::arg("scene"), py::arg("integrators") = py::none(), py::arg("dts") = py::none(),
        py::arg("duration") = py::none(), py::arg("frame_dts") = py::none(),
        py::arg("reference_refinement") = py::none(), py::arg("reference_tolerance") = py::none(),
        py::arg("jobs") = 0, py::arg("csv") = "",
        "bench(scene, integrators=None, dts=None, duration=None, frame_dts=None, reference_refinement=None,\n"
        "      reference_tolerance=None, jobs=0, csv='') -> pandas.DataFrame\n\n"
        "`clothsim bench SCENE` with its options as keywords: every lane at every step over T, its error at\n"
        "T against the reference and its cost. A keyword left None takes the CLI's default (compare's\n"
        "four lanes, the scene's dt x 0.25..8, T = min(scene, 0.5 s, 8000 x the smallest step) rounded to\n"
        "the largest, implicit_euler also at one step per frame), so bench(scene) is `clothsim bench\n"
        "SCENE`'s table. Columns as bench --csv; `csv` writes that file too. Runs with the GIL released;\n"
        "Ctrl-C raises KeyboardInterrupt; bad options raise clothsim.UsageError (a ValueError).");
  m.def("converge", &converge, py::arg("scene"), py::arg("dt") = py::none(), py::arg("integrators") = py::none(),
        py::arg("states") = py::none(), py::arg("max_iterations") = py::none(), py::arg("csv") = "",
        "converge(scene, dt=None, integrators=None, states=None, max_iterations=None, csv='')\n"
        "    -> pandas.DataFrame\n\n"
        "`clothsim converge SCENE` with its options as keywords (None: the CLI's default, dt=1/60,\n"
        "integrators xpbd, projective_dynamics, vbd, implicit_euler, states=5, max_iterations=50): from\n"
        "`states` states along a converged implicit_euler run, one step of each method with\n"
        "1..max_iterations iterations, its distance from the converged backward-Euler step. Columns as\n"
        "converge --csv: scene, method, state, t, iterations, rms_distance, max_distance, gradient_norm,\n"
        "cpu_seconds, wrong; `csv` writes that file too. Runs with the GIL released; Ctrl-C raises\n"
        "KeyboardInterrupt; bad options raise clothsim.UsageError (a ValueError).");
}

}  // namespace clothsim::python
