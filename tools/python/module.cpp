// The `clothsim` Python module (docs/python.md): a second thin front end, beside the CLI, over
// the same libraries: scene (load_scene), core (Simulation), view + render (render), export
// (Export), study (bench, stability, converge), clip (compare). Errors are Python exceptions carrying the
// CLI's one-line messages.
#include <pybind11/pybind11.h>

#include "scene_binding.h"
#include "simulation_binding.h"
#include "export/export_path.h"
#include "io/output_file.h"
#include "render/renderer.h"
#include "scene/scene_parser.h"
#include "study/study.h"

namespace py = pybind11;

namespace clothsim::python {
void bind_render(py::module_& m);
void bind_export(py::module_& m);
void bind_studies(py::module_& m);
void bind_compare(py::module_& m);
}  // namespace clothsim::python

PYBIND11_MODULE(clothsim, m) {
  using namespace clothsim::python;
  m.doc() =
      "clothsim from Python: load a scene, step it with any integrator, read its state as numpy,\n"
      "render it, and export it for Blender and ParaView.\n"
      "The same libraries as the `clothsim` command: results are the CLI's to the last bit.\n"
      "docs/python.md has the tour.";
  m.attr("__version__") = CLOTHSIM_VERSION;  // the CLI's `clothsim --version`
  py::register_exception<clothsim::SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<clothsim::ExportError>(m, "ExportError", PyExc_OSError);
  py::register_exception<clothsim::OutputFileError>(m, "OutputError", PyExc_OSError);
  py::register_exception<clothsim::RenderError>(m, "RenderError", PyExc_RuntimeError);
  py::register_exception<clothsim::analysis::StudyError>(m, "StudyError", PyExc_ValueError);
  bind_scene(m);
  bind_simulation(m);
  bind_render(m);
  bind_export(m);
  bind_studies(m);
  bind_compare(m);
}
