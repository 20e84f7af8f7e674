// clothsim.converge: the study of `clothsim converge` (study/convergence.h) as a pandas
// DataFrame with the CSV's columns, and the same CSV when asked.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <future>
#include <string>
#include <vector>

#include "scene_binding.h"
#include "core/integrators/integrator_kind.h"
#include "render/output_file.h"
#include "study/convergence.h"

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
    if (!kind || !(is_iterative_solver(*kind) || *kind == IntegratorKind::ImplicitEuler))
      throw py::value_error("integrators: \"" + name +
                            "\" is not an iterative method (expected xpbd, projective_dynamics, vbd or implicit_euler)");
    out.push_back(*kind);
  }
  if (out.empty()) throw py::value_error("integrators: no method given");
  return out;
}

// `frame` as converge --csv writes it: a header of its columns, numbers in their shortest exact
// form (Python's repr, as the CLI's %.15g..%.17g), written whole or not at all.
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
      text += py::isinstance<py::str>(cell) ? cell.cast<std::string>() : py::repr(cell).cast<std::string>();
    }
    text += "\n";
  }
  OutputFile file(path);
  if (!write_all(file.fd(), text.data(), text.size())) throw OutputFileError("cannot write " + path);
  file.commit();
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
  py::dict columns;
  const auto column = [&](const char* name, auto value) {
    py::list values;
    for (const ConvergencePoint& p : points) values.append(value(p));
    columns[name] = values;
  };
  column("scene", [&](const ConvergencePoint&) { return model.name; });
  column("method", [](const ConvergencePoint& p) { return std::string(integrator_name(p.method)); });
  column("state", [](const ConvergencePoint& p) { return p.state; });
  column("t", [](const ConvergencePoint& p) { return p.t; });
  column("iterations", [](const ConvergencePoint& p) { return p.iterations; });
  column("rms_distance", [](const ConvergencePoint& p) { return p.rms; });
  column("max_distance", [](const ConvergencePoint& p) { return p.max; });
  column("gradient_norm", [](const ConvergencePoint& p) { return p.gradient; });
  column("cpu_seconds", [](const ConvergencePoint& p) { return p.cpu_seconds; });
  py::object frame = py::module_::import("pandas").attr("DataFrame")(columns);
  if (!csv.empty()) write_csv(csv, frame);
  return frame;
}

}  // namespace

void bind_studies(py::module_& m) {
  m.def("converge", &converge, py::arg("scene"), py::arg("dt") = 1.0 / 60.0,
        py::arg("integrators") = std::vector<std::string>{"xpbd", "projective_dynamics", "vbd", "implicit_euler"},
        py::arg("states") = 5, py::arg("max_iterations") = 50, py::arg("csv") = "",
        "converge(scene, dt=1/60, integrators=['xpbd', 'projective_dynamics', 'vbd', 'implicit_euler'],\n"
        "         states=5, max_iterations=50, csv='') -> pandas.DataFrame\n\n"
        "`clothsim converge`: from `states` states along a converged implicit_euler run, one step of\n"
        "each method with 1..max_iterations iterations, its distance from the converged backward-Euler\n"
        "step. Columns as converge --csv: scene, method, state, t, iterations, rms_distance,\n"
        "max_distance, gradient_norm, cpu_seconds; `csv` writes that file too. Runs with the GIL\n"
        "released; Ctrl-C raises KeyboardInterrupt.");
}

}  // namespace clothsim::python
