#include "scene_binding.h"

#include <cmath>
#include <cstdio>
#include <optional>

#include "clip/common/install_paths.h"
#include "clip/common/memory_budget.h"
#include "io/output_file.h"
#include "core/integrators/integrator_kind.h"
#include "scene/build_model.h"
#include "scene/param_keys.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"

namespace py = pybind11;

namespace clothsim::python {
namespace {

// A Python value as the YAML text --set takes: numbers at full precision, booleans as YAML's,
// lists as flow sequences, strings as they are.
std::string yaml_value(const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return std::to_string(value.cast<long long>());
  if (py::isinstance<py::float_>(value)) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value.cast<double>());
    return text;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string out = "[";
    for (const py::handle item : value) out += (out.size() > 1 ? ", " : "") + yaml_value(item);
    return out + "]";
  }
  return py::str(value).cast<std::string>();
}

// "KEY=VALUE" strings for the parser; a glob or alias (ks, kd, cloth.springs.*.stiffness)
// becomes one per spring type the scene declares, as compare --vary's keys do.
std::vector<std::string> overrides(const std::string& path, const py::dict& set) {
  std::vector<std::string> out;
  std::optional<SceneDef> plain;  // the scene without --set, to resolve globs against
  for (const auto& [key_handle, value] : set) {
    const std::string key = py::str(key_handle).cast<std::string>();
    if (key.find('*') == std::string::npos && key != "ks" && key != "kd") {
      out.push_back(key + "=" + yaml_value(value));
      continue;
    }
    if (!plain) plain = clothsim::load_scene(path, {}, false);
    try {
      const ParamKey resolved = resolve_param_key(key, *plain);
      for (const std::string& p : resolved.paths) out.push_back(p + "=" + yaml_value(value));
    } catch (const ParamKeyError& e) {
      throw SceneError(path, 0, key, e.what());
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> set_strings(const std::string& path, const py::dict& set) { return overrides(path, set); }

std::string option_text(const py::object& value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string out;
    for (const py::handle item : value) out += (out.empty() ? "" : ",") + py::str(item).cast<std::string>();
    return out;
  }
  return py::str(value).cast<std::string>();
}

std::optional<double> max_memory_keyword(const py::object& value) {
  if (value.is_none()) return std::nullopt;
  return clip::max_memory_option(option_text(value));
}

Scene load_scene(const std::string& given, const py::dict& set, py::object duration, py::object dt,
                 py::object integrator) {
  // A NUL would end the name at the system call: 'spring.yaml\0.evil' must not load spring.yaml.
  if (given.find('\0') != std::string::npos) throw py::value_error("load_scene: the path holds a NUL character");
  const std::string path = clip::resolve_scene_argument(given);  // a shipped scene by bare name, as the CLI
  const bool replaced = !duration.is_none() || !dt.is_none();
  std::vector<std::string> sets = overrides(path, set);
  SceneDef def = clothsim::load_scene(path, sets, /*bound_run=*/!replaced);
  if (!duration.is_none()) {
    def.duration = duration.cast<double>();
    if (!(def.duration >= 0.0) || !std::isfinite(def.duration))
      throw py::value_error("duration: must be a finite number >= 0 s");
  }
  if (!dt.is_none()) {
    def.dt = dt.cast<double>();
    if (!(def.dt > 0.0) || !std::isfinite(def.dt)) throw py::value_error("dt: must be a finite number > 0 s");
  }
  if (!integrator.is_none()) {
    const auto kind = parse_integrator(integrator.cast<std::string>());
    if (!kind) throw py::value_error("integrator: unknown name (one of " + integrator_names_joined() + ")");
    def.integrator = *kind;
  }
  if (replaced) {
    const std::string too_long = run_bounds_problem(def.duration, def.dt, def.render.fps);
    if (!too_long.empty()) throw py::value_error(too_long);
  }
  Scene scene{def, std::make_shared<const Model>(build_model(def)), std::move(sets), {}, {}};
  protect_input(path, "the scene");  // no Export or render of this process writes through it
  if (!duration.is_none()) scene.duration = def.duration;
  if (!dt.is_none()) scene.dt = def.dt;
  return scene;
}

void bind_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", "A validated scene (scenes/*.yaml) and the model built from it.")
      // Scene(path) is load_scene(path); with the conversion below, every call that takes a
      // Scene (Simulation, bench, stability, converge, compare, Export) takes a path too.
      .def(py::init([](const std::string& path) { return load_scene(path, py::dict(), py::none(), py::none(), py::none()); }),
           py::arg("path"))
      .def_property_readonly("name", [](const Scene& s) { return s.def.name; })
      .def_property_readonly("source", [](const Scene& s) { return s.def.source; })
      .def_property_readonly("duration", [](const Scene& s) { return s.def.duration; }, "Simulated time, s.")
      .def_property_readonly("dt", [](const Scene& s) { return s.def.dt; }, "The scene's step, s.")
      .def_property_readonly("integrator", [](const Scene& s) { return std::string(integrator_name(s.def.integrator)); })
      .def_property_readonly("fps", [](const Scene& s) { return s.def.render.fps; }, "Output frames per second.")
      .def_property_readonly("particles", [](const Scene& s) { return s.model->num_particles; })
      .def_property_readonly("spheres", [](const Scene& s) { return s.model->num_spheres; })
      .def("__repr__", [](const Scene& s) {
        return "<clothsim.Scene " + s.def.name + ": " + std::to_string(s.model->num_particles) + " particles, " +
               std::to_string(s.model->num_spheres) + " spheres, " + std::string(integrator_name(s.def.integrator)) + ">";
      });
  py::implicitly_convertible<py::str, Scene>();
  m.def("load_scene", &load_scene, py::arg("path"), py::arg("set") = py::dict(), py::arg("duration") = py::none(),
        py::arg("dt") = py::none(), py::arg("integrator") = py::none(),
        "load_scene(path, set={}, duration=None, dt=None, integrator=None) -> Scene\n\n"
        "Reads and validates a scene file as `clothsim run` does (a bare name such as\n"
        "'drape_smooth' is a shipped scene when no such file is here). `set` holds the --set keys\n"
        "({'cloth.springs.shear.stiffness': 2e4, 'render.fps': 60}), the aliases ks and kd (every\n"
        "spring type's stiffness and damping) and globs (cloth.springs.*.damping); duration, dt\n"
        "and integrator replace the scene's as --duration, --dt and --integrator do.\n"
        "Raises clothsim.SceneError with the CLI's one-line message (FILE:LINE: KEY: what).");
}

}  // namespace clothsim::python
