// clothsim.render: a Simulation's current state pictured by the renderer `clothsim run` uses
// (render/renderer.h: EGL, else OSMesa, or CLOTHSIM_GL), as a numpy (H, W, 3) uint8 image.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <mutex>

#include "simulation_binding.h"
#include "render/renderer.h"
#include "view/snapshot.h"
#include "view/vertex_fields.h"

namespace py = pybind11;

namespace clothsim::python {
namespace {

// One GL context for the process, made at the first picture (it takes a few hundred ms), and
// one thread at a time in it: EGL refuses a context current on another thread (four threads
// rendering at once got "eglMakeCurrent failed (EGL error 0x3002)"), and the GL entry points
// are the process's. Taken with the GIL released; the Renderer releases the context after each
// picture, so whichever thread comes next may make it current.
std::mutex gl_mutex;

Image render_locked(const RenderFrame& frame) {
  static std::unique_ptr<Renderer> r;
  const std::lock_guard<std::mutex> held(gl_mutex);
  if (!r) r = std::make_unique<Renderer>();  // (a failure leaves none, and the next call tries again)
  return r->render(frame);
}

py::array_t<std::uint8_t> render(const Simulation& sim, int width, int height, const std::string& color,
                                 std::optional<std::pair<double, double>> color_range) {
  const Model& model = sim.engine().model();
  const RenderDef& look = sim.scene().def.render;
  std::unique_lock<std::mutex> held = sim.lock();  // the state as one thread left it, not as another steps it
  const State& state = sim.engine().state();
  RenderFrame frame = make_render_frame(model, state, look);
  frame.width = width;
  frame.height = height;
  if (look.camera_auto) frame.camera = fit_scene_camera(model, look, static_cast<double>(width) / height);
  const auto kind = parse_field_kind(color);
  if (!kind || *kind == FieldKind::Error)
    throw py::value_error("color: " + color + ": one of checker, strain, speed (error needs compare's reference)");
  if (*kind != FieldKind::None) {
    frame.cloth_field = *kind == FieldKind::Strain ? vertex_strain(model, state) : vertex_speed(model, state);
    const std::pair<double, double> range =
        color_range.value_or(*kind == FieldKind::Strain ? std::make_pair(1e-4, 1e-1) : std::make_pair(1e-3, 1.0));
    frame.color_scale.lo = static_cast<float>(range.first);
    frame.color_scale.hi = static_cast<float>(range.second);
    frame.color_scale.log = true;
    frame.color_scale.label = field_label(*kind);
  }
  held.unlock();  // the frame is a copy
  Image image;
  {
    py::gil_scoped_release release;
    image = render_locked(frame);
  }
  py::array_t<std::uint8_t> out({height, width, 3});
  auto px = out.mutable_unchecked<3>();
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) px(y, x, c) = image.pixel(x, y)[c];
  return out;
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("render", &render, py::arg("sim"), py::arg("width") = 640, py::arg("height") = 360,
        py::arg("color") = "checker", py::arg("color_range") = py::none(),
        "render(sim, width=640, height=360, color='checker', color_range=None) -> numpy (H, W, 3) uint8\n\n"
        "The current state of `sim` as `clothsim run` draws it (the scene's camera, render.camera auto\n"
        "included; no overlay text), through the same renderer: EGL, else OSMesa (CLOTHSIM_GL=egl|osmesa\n"
        "chooses). color: checker, strain or speed, on a log scale color_range=(lo, hi) (default\n"
        "strain 1e-4..1e-1, speed 1e-3..1 m/s). Raises clothsim.RenderError when no GL context can be made.");
}

}  // namespace clothsim::python
