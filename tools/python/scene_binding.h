// clothsim.load_scene and the Scene it returns: the scene library's parser with --set's keys
// (and the ks / kd aliases of compare --vary, resolved against the scene).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "core/model.h"
#include "scene/scene_def.h"

namespace clothsim::python {

// A loaded scene and its Model, built once and shared by the Simulations made from it.
struct Scene {
  SceneDef def;
  std::shared_ptr<const Model> model;
  std::vector<std::string> overrides;  // the --set strings it was loaded with (studies reload it)
};

// set: {"cloth.springs.shear.stiffness": 2e4, "ks": 5e3, "integrator": "rk4", ...}
Scene load_scene(const std::string& path, const pybind11::dict& set, pybind11::object duration,
                 pybind11::object dt, pybind11::object integrator);

// A `set` dict as --set's KEY=VALUE strings (globs and the ks / kd aliases resolved against
// the scene at `path`), as load_scene reads it.
std::vector<std::string> set_strings(const std::string& path, const pybind11::dict& set);

void bind_scene(pybind11::module_& m);

}  // namespace clothsim::python
