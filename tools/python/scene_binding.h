// clothsim.load_scene and the Scene it returns: the scene library's parser with --set's keys
// (and the ks / kd aliases of compare --vary, resolved against the scene).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model/model.h"
#include "scene/scene_def.h"

namespace clothsim::python {

// A loaded scene and its Model, built once and shared by the Simulations made from it.
struct Scene {
  SceneDef def;
  std::shared_ptr<const Model> model;
  std::vector<std::string> overrides;  // the --set strings it was loaded with (studies reload it)
  std::optional<double> duration, dt;  // load_scene's duration= and dt=, as --duration and --dt
};

// A keyword argument as the CLI's option text: a str as it is, a list or tuple joined by
// commas (["rk4@1e-4", "vbd:10"], [1e-4, 2e-4]: floats in their shortest exact spelling).
std::string option_text(const pybind11::object& value);

// max_memory=: None (the CLI's default budget), or --max-memory's SIZE ("4G", 512e6 bytes) read
// by the CLI's own parser (clip/common/memory_budget.h), a bad one raising its UsageError.
std::optional<double> max_memory_keyword(const pybind11::object& value);

// set: {"cloth.springs.shear.stiffness": 2e4, "ks": 5e3, "integrator": "rk4", ...}
Scene load_scene(const std::string& path, const pybind11::dict& set, pybind11::object duration,
                 pybind11::object dt, pybind11::object integrator);

// A `set` dict as --set's KEY=VALUE strings (globs and the ks / kd aliases resolved against
// the scene at `path`), as load_scene reads it.
std::vector<std::string> set_strings(const std::string& path, const pybind11::dict& set);

void bind_scene(pybind11::module_& m);

}  // namespace clothsim::python
