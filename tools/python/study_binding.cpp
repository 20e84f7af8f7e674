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
#include "study/csv_cells.h"
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

// `frame` as the CLI's --csv writes it: a header of its columns, each cell as study/csv_cells.h
// spells it (text quoted where needed, numbers in their shortest exact form), whole or not at all.
void write_csv(const std::string& path, const py::object& frame) {
  const py::list names = frame.attr("columns").attr("tolist")();
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i ? "," : "") + names[i].cast<std::string>();
  text += "\n";
  for (const py::handle row : frame.attr("itertuples")(py::arg("index") = false, py::arg("name") = py::none())) {
    bool first = true;
    for (const py::handle cell : row) {
      text += first ? "" : ",";
      first = false;
      text += py::isinstance<py::str>(cell) ? analysis::csv_text(cell.cast<std::string>())
                                            : analysis::csv_number(py::float_(py::reinterpret_borrow<py::object>(cell)));
    }
    text += "\n";
  }
  OutputFile file(path);
  if (!write_all(file.fd(), text.data(), text.size())) throw OutputFileError("cannot write " + path);
  file.commit();
}

// Columns of points, one list per name, as a DataFrame (in the order given).
template <typename Point>
py::object data_frame(const std::vector<Point>& points,
                      const std::vector<std::pair<const char*, std::function<py::object(const Point&)>>>& columns) {
  py::dict data;
  for (const auto& [name, value] : columns) {
    py::list values;
    for (const Point& p : points) values.append(value(p));
    data[name] = values;
  }
  return py::module_::import("pandas").attr("DataFrame")(data);
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
  using P = ConvergencePoint;
  const auto number = [](double v) { return py::object(py::float_(v)); };
  const auto integer = [](long long v) { return py::object(py::int_(v)); };
  py::object frame = data_frame<P>(
      points, {{"scene", [&](const P&) { return py::object(py::str(model.name)); }},
               {"method", [](const P& p) { return py::object(py::str(std::string(integrator_name(p.method)))); }},
               {"state", [&](const P& p) { return integer(p.state); }},
               {"t", [&](const P& p) { return number(p.t); }},
               {"iterations", [&](const P& p) { return integer(p.iterations); }},
               {"rms_distance", [&](const P& p) { return number(p.rms); }},
               {"max_distance", [&](const P& p) { return number(p.max); }},
               {"gradient_norm", [&](const P& p) { return number(p.gradient); }},
               {"cpu_seconds", [&](const P& p) { return number(p.cpu_seconds); }},
               {"wrong", [](const P& p) { return py::object(py::str(p.wrong)); }}});
  if (!csv.empty()) write_csv(csv, frame);
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
  using P = analysis::WorkPrecisionPoint;
  const auto number = [](double v) { return py::object(py::float_(v)); };
  py::object frame = data_frame<P>(
      r.points,
      {{"integrator", [](const P& p) { return py::object(py::str(std::string(integrator_name(p.integrator)))); }},
       {"dt", [&](const P& p) { return number(p.dt); }},
       {"steps", [](const P& p) { return py::object(py::int_(p.steps)); }},
       {"force_evals", [](const P& p) { return py::object(py::int_(p.force_evals)); }},
       {"newton_iterations", [](const P& p) { return py::object(py::int_(p.newton_iterations)); }},
       {"cg_iterations", [](const P& p) { return py::object(py::int_(p.cg_iterations)); }},
       {"wall_seconds", [&](const P& p) { return number(p.wall_seconds); }},
       {"cpu_seconds", [&](const P& p) { return number(p.cpu_seconds); }},
       {"rms_error", [&](const P& p) { return number(p.unresolved ? NAN : p.rms_error); }},
       {"max_error", [&](const P& p) { return number(p.unresolved ? NAN : p.max_error); }},
       {"diverged", [](const P& p) { return py::object(py::int_(p.diverged ? 1 : 0)); }},
       {"diverged_at", [&](const P& p) { return p.diverged ? number(p.diverged_at) : py::object(py::str("")); }},
       {"reason", [](const P& p) { return py::object(py::str(p.reason)); }},
       {"duration", [&](const P&) { return number(r.duration); }},
       {"reference_dt", [&](const P&) { return number(r.reference.dt); }},
       {"reference_change", [&](const P&) { return number(r.reference.finished ? r.reference.change_rms : NAN); }},
       {"unconverged_steps", [](const P& p) { return py::object(py::int_(p.unconverged_steps)); }},
       {"wrong", [](const P& p) { return py::object(py::int_(p.wrong ? 1 : 0)); }},
       {"wrong_at", [&](const P& p) { return p.wrong ? number(p.wrong_at) : py::object(py::str("")); }},
       {"wrong_reason", [](const P& p) { return py::object(py::str(p.wrong_reason)); }},
       {"unresolved", [](const P& p) { return py::object(py::int_(p.unresolved ? 1 : 0)); }}});
  if (!csv.empty()) write_csv(csv, frame);
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
  using L = StabilityLimit;
  const auto number = [](double v) { return py::object(py::float_(v)); };
  const auto text = [](const std::string& t) { return py::object(py::str(t)); };
  py::object frame = data_frame<L>(
      limits,
      {{"param", [&](const L&) { return text(param); }},
       {"value", [&](const L& l) { return number(l.value); }},
       {"integrator", [&](const L& l) { return text(std::string(integrator_name(l.integrator))); }},
       {"outcome", [&](const L& l) { return text(analysis::outcome_name(l.outcome)); }},
       {"stable_dt", [&](const L& l) { return number(l.stable_dt); }},
       {"unstable_dt", [&](const L& l) { return number(l.unstable_dt); }},
       {"trials", [](const L& l) { return py::object(py::int_(l.trials)); }},
       {"cpu_seconds", [&](const L& l) { return number(l.cpu_seconds); }},
       {"w_max", [&](const L& l) { return number(l.estimate.w_max); }},
       {"c_max", [&](const L& l) { return number(l.estimate.c_max); }},
       {"dt_springs", [&](const L& l) { return number(l.estimate.dt_springs()); }},
       {"dt_with_damping", [&](const L& l) { return number(l.estimate.dt_with_damping()); }},
       {"duration", [&](const L&) { return number(spec.duration); }},
       {"min_dt", [&](const L&) { return number(spec.min_dt); }},
       {"max_dt", [&](const L&) { return number(spec.max_dt); }},
       {"precision", [&](const L&) { return number(spec.precision); }},
       {"reason", [&](const L& l) { return text(l.reason); }},
       {"failure", [&](const L& l) { return text(analysis::failure_name(l.failure)); }},
       {"frame_steps", [&](const L& l) {
          std::string out;
          for (const analysis::FrameStepResult& r : l.frame_steps) out += (out.empty() ? "" : "; ") + analysis::frame_step_text(r);
          return text(out);
        }}});
  if (!csv.empty()) write_csv(csv, frame);
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
