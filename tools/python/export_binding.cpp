// clothsim.Export: mesh export (export/mesh_export.h) of a Simulation's frames, the files
// `run --export` writes.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>

#include "simulation_binding.h"
#include "export/mesh_export.h"

namespace py = pybind11;

namespace clothsim::python {
namespace {

struct Export {
  Scene scene;  // keeps the model alive
  std::unique_ptr<MeshExport> out;
  int frame = 0;
};

}  // namespace

void bind_export(py::module_& m) {
  py::class_<Export>(m, "Export",
                     "Export(scene, path, fps=None)\n\n"
                     "Mesh export as `clothsim run --export PATH` writes it: DIR/frame_%05d.obj or .ply (a\n"
                     "file per frame), NAME.pc2 (Point Cache 2 beside NAME.obj, for Blender's Mesh Cache\n"
                     "modifier), NAME.pvd (VTK .vtp per frame in NAME/, for ParaView). add(sim) writes the\n"
                     "next frame (frame k at k / fps, fps the scene's by default); finish() names the PC2 or\n"
                     "PVD. Files appear whole or not at all. Raises clothsim.ExportError.")
      .def(py::init([](Scene scene, const std::string& path, std::optional<double> fps) {
             if (path.find('\0') != std::string::npos) throw py::value_error("Export: the path holds a NUL character");
             const double rate = fps.value_or(scene.def.render.fps);
             // A PVD's times are k / fps: a rate that is not a finite positive number would write inf or nan.
             if (!(rate > 0.0) || !std::isfinite(rate)) throw py::value_error("Export: fps must be a finite number > 0");
             auto out = std::make_unique<MeshExport>(*scene.model, parse_export_path(path), rate, false);
             return Export{std::move(scene), std::move(out), 0};
           }),
           py::arg("scene"), py::arg("path"), py::arg("fps") = py::none())
      .def(
          "add",
          [](Export& e, const Simulation& sim) {
            // Of this scene even when its lane's settings (vbd@1/60:3) gave it a model of its own:
            // the same particles and triangles.
            if (!sim.of_scene(e.scene)) throw py::value_error("Export.add: the Simulation is of another scene");
            const auto held = sim.lock();
            e.out->add(e.frame++, sim.engine().state());
          },
          py::arg("sim"), "Writes the Simulation's current state as the next frame.")
      .def("finish", [](Export& e) { e.out->finish(); }, "Names what is named at the end (PC2, PVD).")
      .def_property_readonly("written", [](const Export& e) { return e.out->written_files(); },
                             "The files on disk, a list of paths: every per-frame file in the order written, then\n"
                             "what finish() named (['c.pc2', 'c.obj', ...]).")
      .def_property_readonly("summary", [](const Export& e) { return e.out->written(); },
                             "What is on disk in words, as the CLI says it: '12 OBJ files in out/', 'c.pc2, c.obj'.");
}

}  // namespace clothsim::python
