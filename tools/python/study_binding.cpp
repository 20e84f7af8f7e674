// clothsim.converge: the study of `clothsim converge` (study/convergence.h) as a pandas
// DataFrame with the CSV's columns, and the same CSV when asked.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <future>
#include <string>
#include <vector>

#include "scene_binding.h"
#include "core/integrators/integrator_kind.h"
#include "render/output_file.h"
#include "scene/build_model.h"
#include "scene/param_keys.h"
#include "scene/scene_parser.h"
#include "study/convergence.h"
#include "study/tables/csv_tables.h"
#include "study/parameter_sweep.h"
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

std::vector<IntegratorKind> methods_of(const std::vector<std::string>& names) {
  std::vector<IntegratorKind> out;
  for (const std::string& name : names) {
    const auto kind = parse_integrator(name);
    if (!kind || integrator_info(*kind).iterations == IterationControl::None)
      throw py::value_error("integrators: \"" + name +
                            "\" is not an iterative method (expected xpbd, projective_dynamics, vbd or implicit_euler)");
    out.push_back(*kind);
  }
  if (out.empty()) throw py::value_error("integrators: no method given");
  return out;
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

// Each integrator's name, by lane (the module's lanes are plain integrators).
std::vector<std::string> names_of(const std::vector<IntegratorKind>& kinds) {
  std::vector<std::string> out;
  for (IntegratorKind k : kinds) out.emplace_back(integrator_name(k));
  return out;
}

py::object converge(const Scene& scene, double dt, const std::vector<std::string>& integrators, int states,
                    int max_iterations, const std::string& csv) {
  if (!(dt > 0.0)) throw py::value_error("dt: must be a step > 0 s");
  if (states < 1 || max_iterations < 1) throw py::value_error("states, max_iterations: must be at least 1");
  ConvergenceSpec spec;
  spec.h = dt;
  spec.states = states;
  spec.max_iterations = max_iterations;
  spec.methods = methods_of(integrators);
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

std::vector<IntegratorKind> kinds_of(const std::vector<std::string>& names) {
  std::vector<IntegratorKind> out;
  for (const std::string& name : names) {
    const auto kind = parse_integrator(name);
    if (!kind) throw py::value_error("integrators: unknown name " + name + " (one of " + integrator_names_joined() + ")");
    out.push_back(*kind);
  }
  return out;
}

py::object bench(const Scene& scene, const std::vector<std::string>& integrators, const std::vector<double>& dts,
                 double duration, const std::vector<double>& frame_dts, int reference_refinement, int jobs,
                 const std::string& csv) {
  analysis::WorkPrecisionSpec spec;
  spec.integrators = kinds_of(integrators);
  spec.dts = dts;
  spec.frame_dts = frame_dts;
  spec.duration = duration;
  spec.reference_refinement = reference_refinement;
  spec.jobs = jobs;
  spec = analysis::checked(spec);
  const Model& model = *scene.model;
  const analysis::WorkPrecisionResult r = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::work_precision(model, spec, hooks);
  });
  const analysis::CsvTable table = analysis::work_precision_table(r, names_of(spec.integrators));
  py::object frame = data_frame(table);
  if (!csv.empty()) write_csv(csv, table);
  return frame;
}

py::object stability(const Scene& scene, const std::vector<std::string>& integrators, const std::string& param,
                     const std::vector<double>& values, double duration, double min_dt, double max_dt,
                     double precision, const std::vector<double>& frame_dts, int jobs, const std::string& csv) {
  using analysis::StabilityLimit;
  analysis::StabilitySpec spec;
  spec.integrators = kinds_of(integrators);
  spec.duration = duration;
  spec.min_dt = min_dt;
  spec.max_dt = max_dt;
  spec.precision = precision;
  spec.frame_dts = frame_dts;
  spec.jobs = jobs;
  analysis::check(spec);
  ParamKey key;
  try {
    key = resolve_param_key(param, scene.def);
  } catch (const ParamKeyError& e) {
    throw py::value_error("param " + std::string(e.what()));
  }
  const std::vector<analysis::SweepScene> scenes =
      analysis::sweep_scenes(scene.def.source, scene.overrides, key.paths, values);
  std::vector<Model> models;
  models.reserve(scenes.size());
  std::vector<analysis::StabilityCase> cases;
  for (const analysis::SweepScene& s : scenes) {
    models.push_back(build_model(s.scene));
    cases.push_back({s.value, &models.back(), {}});
  }
  const std::vector<StabilityLimit> limits = interruptible([&](auto stop) {
    analysis::StudyHooks hooks;
    hooks.stop = stop;
    return analysis::stability_sweep(cases, spec, hooks);
  });
  const analysis::CsvTable table = analysis::stability_table(limits, spec, param, names_of(spec.integrators));
  py::object frame = data_frame(table);
  if (!csv.empty()) write_csv(csv, table);
  return frame;
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def("stability", &stability, py::arg("scene"), py::arg("integrators"),
        py::arg("param") = "cloth.springs.structural.stiffness", py::arg("values"), py::arg("duration"),
        py::arg("min_dt"), py::arg("max_dt"), py::arg("precision") = 0.02, py::arg("frame_dts") = std::vector<double>{},
        py::arg("jobs") = 0, py::arg("csv") = "",
        "stability(scene, integrators, param='cloth.springs.structural.stiffness', values, duration, min_dt,\n"
        "          max_dt, precision=0.02, frame_dts=[], jobs=0, csv='') -> pandas.DataFrame\n\n"
        "`clothsim stability --param P --values ... --duration T --min-dt ... --max-dt ...`: for each value of\n"
        "the scene key `param` (a path, a glob or ks / kd), each integrator's largest stable step over T,\n"
        "bracketed to `precision`. Columns as stability --csv; `csv` writes that file too. The range and\n"
        "T are given here (stability's defaults are the CLI's). GIL released; Ctrl-C: KeyboardInterrupt.");
  m.def("bench", &bench, py::arg("scene"), py::arg("integrators"), py::arg("dts"), py::arg("duration"),
        py::arg("frame_dts") = std::vector<double>{}, py::arg("reference_refinement") = 8, py::arg("jobs") = 0,
        py::arg("csv") = "",
        "bench(scene, integrators, dts, duration, frame_dts=[], reference_refinement=8, jobs=0, csv='')\n"
        "    -> pandas.DataFrame\n\n"
        "`clothsim bench --integrators ... --dts ... --duration T --frame-dts ...`: every integrator at every\n"
        "step over T (each step dividing T), its error at T against an RK4 reference and its cost. Columns\n"
        "as bench --csv; `csv` writes that file too. The steps and T are given here (bench's defaults are\n"
        "the CLI's). Runs with the GIL released; Ctrl-C raises KeyboardInterrupt.");
  m.def("converge", &converge, py::arg("scene"), py::arg("dt") = 1.0 / 60.0,
        py::arg("integrators") = std::vector<std::string>{"xpbd", "projective_dynamics", "vbd", "implicit_euler"},
        py::arg("states") = 5, py::arg("max_iterations") = 50, py::arg("csv") = "",
        "converge(scene, dt=1/60, integrators=['xpbd', 'projective_dynamics', 'vbd', 'implicit_euler'],\n"
        "         states=5, max_iterations=50, csv='') -> pandas.DataFrame\n\n"
        "`clothsim converge`: from `states` states along a converged implicit_euler run, one step of\n"
        "each method with 1..max_iterations iterations, its distance from the converged backward-Euler\n"
        "step. Columns as converge --csv: scene, method, state, t, iterations, rms_distance,\n"
        "max_distance, gradient_norm, cpu_seconds, wrong; `csv` writes that file too. Runs with the GIL\n"
        "released; Ctrl-C raises KeyboardInterrupt.");
}

}  // namespace clothsim::python
