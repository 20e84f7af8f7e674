// clothsim.compare: `clothsim compare` through the same library (clip/compare/compare_job.h),
// the CLI's options as keyword arguments, the lanes' summary objects as a DataFrame, and the
// same files when asked. Runs with the GIL released; Ctrl-C stops the lanes as SIGINT stops
// the CLI's (nothing partial stays) and raises KeyboardInterrupt.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <csignal>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scene_binding.h"
#include "clip/common/cli_common.h"
#include "clip/compare/compare_job.h"
#include "core/integrators/integrator_kind.h"

namespace py = pybind11;

namespace clothsim::python {
namespace {

using clip::CompareRequest;

// `match`: "cost", "none", "error 1e-3" or ("error", 1e-3), as --match's words.
std::vector<std::string> match_words(const py::object& match) {
  if (py::isinstance<py::str>(match)) {
    std::vector<std::string> words = split_list(match.cast<std::string>(), ' ');
    return words;
  }
  std::vector<std::string> words;
  for (const py::handle w : match) words.push_back(py::str(w).cast<std::string>());
  return words;
}

// %.17g: the number back exactly when the scene parser reads it.
std::string exact_number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

// Runs the plan on its own thread with the GIL released, checking Python's signals every
// 0.1 s: a KeyboardInterrupt asks the lanes to stop (as SIGINT does the CLI's), waits for the
// outputs to be dropped, and is raised.
clip::PipelineReport run_interruptible(const CompareRequest& o, clip::ComparePlan& p,
                                       std::vector<clip::LaneFrameRow>& rows) {
  clip::clear_interrupt();
  auto work = std::async(std::launch::async, [&]() -> std::optional<clip::PipelineReport> {
    std::optional<clip::ComparePlan> part = clip::plan_compare_part(o);
    if (!part) return clip::PipelineReport{};  // a part with no lane
    p = std::move(*part);
    return clip::run_compare(o, p, &rows);
  });
  for (;;) {
    {
      py::gil_scoped_release release;
      if (work.wait_for(std::chrono::milliseconds(100)) == std::future_status::ready) break;
    }
    if (PyErr_CheckSignals() != 0) {
      py::error_already_set interrupt;  // KeyboardInterrupt (or whatever the handler raised)
      clip::request_interrupt(SIGINT);
      {
        py::gil_scoped_release release;
        work.wait();
      }
      clip::clear_interrupt();
      try {
        work.get();
      } catch (const clip::RuntimeFailure&) {  // "stopped by SIGINT ...": the outputs dropped
      }
      throw interrupt;
    }
  }
  return *work.get();
}

// The lanes' rows per clip frame as a DataFrame, the values themselves (no text between): lane
// and name as the table's, the frame's time, --metrics' columns under their names (run_outputs.h),
// and the colouring field's largest value under its kind's name (error, strain, speed).
py::object frames_frame(const clip::ComparePlan& p, const std::vector<clip::LaneFrameRow>& rows) {
  std::vector<std::string> lane, name, scene, integrator;
  std::vector<std::int64_t> step, force_evals, newton_iterations, cg_iterations, rejected_steps;
  std::vector<int> contacts;
  std::vector<double> frame_t, t, kinetic, spring, gravity, total, max_strain, residual, dt, step_size, field;
  std::vector<bool> converged;
  std::vector<std::string> scenes, methods;  // per lane: as run --metrics names them (its settings')
  for (const clip::CompareLane& l : p.lanes) {
    const Model& model = l.model ? *l.model : *p.model;
    scenes.push_back(model.name);
    methods.push_back(method_name(l.spec.kind, clip::lane_settings(model, l.spec).implicit));
  }
  for (const clip::LaneFrameRow& r : rows) {
    const clip::CompareLane& l = p.lanes[r.lane];
    const FrameMetrics& m = r.metrics;
    lane.push_back(l.spec.spelling()), name.push_back(l.name), frame_t.push_back(r.frame_t);
    step.push_back(m.step), t.push_back(m.t);
    kinetic.push_back(m.energies.kinetic), spring.push_back(m.energies.spring), gravity.push_back(m.energies.gravity);
    total.push_back(m.energies.total()), max_strain.push_back(m.max_strain), contacts.push_back(m.contacts);
    force_evals.push_back(m.force_evals), newton_iterations.push_back(m.newton_iterations);
    cg_iterations.push_back(m.cg_iterations), residual.push_back(m.residual), converged.push_back(m.converged);
    scene.push_back(scenes[r.lane]), integrator.push_back(methods[r.lane]);
    dt.push_back(l.spec.dt), step_size.push_back(m.step_size), rejected_steps.push_back(m.rejected_steps);
    field.push_back(r.field);
  }
  py::dict columns;
  columns["lane"] = lane, columns["name"] = name, columns["frame_t"] = frame_t;
  columns["step"] = step, columns["t"] = t, columns["kinetic"] = kinetic, columns["spring_potential"] = spring;
  columns["gravity_potential"] = gravity, columns["total_energy"] = total, columns["max_strain"] = max_strain;
  columns["contacts"] = contacts, columns["force_evals"] = force_evals;
  columns["newton_iterations"] = newton_iterations, columns["cg_iterations"] = cg_iterations;
  columns["residual"] = residual, columns["converged"] = converged, columns["scene"] = scene;
  columns["integrator"] = integrator, columns["dt"] = dt, columns["step_size"] = step_size;
  columns["rejected_steps"] = rejected_steps;
  if (p.look.color != FieldKind::None) columns[py::str(std::string(field_kind_name(p.look.color)))] = field;
  return py::module_::import("pandas").attr("DataFrame")(columns);
}

// `unresolved`, a verdict --summary gives the lanes and not the reference, is False on the
// reference's row: a boolean column (frame[frame.unresolved]), as the studies' verdicts are.
void unresolved_as_booleans(py::object& frame) {
  if (!py::bool_(frame.attr("columns").attr("__contains__")("unresolved"))) return;
  frame["unresolved"] = frame["unresolved"].attr("fillna")(false).attr("astype")("bool");
}

py::object compare(const py::object& scene, const py::dict& set, const py::object& integrators,
                   const py::object& match, const std::string& vary, const py::object& dt,
                   const std::optional<double>& duration, const std::string& layout, const std::string& video,
                   const std::string& frames, const std::string& sheet, const py::object& times,
                   const std::optional<double>& still, const std::string& output, const std::string& export_path,
                   const std::string& summary, const std::optional<std::string>& color, const py::object& color_range,
                   const std::string& reference, const std::optional<std::string>& overlay,
                   const std::string& overlay_cost, const std::string& inset, const std::optional<int>& width,
                   const std::optional<int>& height, const std::optional<double>& fps, const std::string& gl,
                   const std::optional<std::string>& camera, const std::optional<std::string>& antialias,
                   const std::optional<int>& crf, const std::optional<std::string>& preset, const std::string& shard,
                   const py::object& max_memory) {
  CompareRequest o;
  if (py::isinstance<py::str>(scene)) {  // a path
    o.scene.path = scene.cast<std::string>();
  } else {  // a loaded Scene: its file and its --set strings, then `set`'s
    const Scene& loaded = scene.cast<const Scene&>();
    o.scene.path = loaded.def.source;
    o.scene.sets = loaded.overrides;
    if (loaded.dt) o.scene.sets.push_back("dt=" + exact_number(*loaded.dt));  // the scene's step, as loaded
  }
  for (std::string& s : set_strings(o.scene.path, set)) o.scene.sets.push_back(std::move(s));
  o.scene.duration = duration;
  if (!duration && py::isinstance<Scene>(scene)) o.scene.duration = scene.cast<const Scene&>().duration;
  o.scene.width = width;
  o.scene.height = height;
  o.scene.fps = fps;
  o.scene.max_memory = max_memory_keyword(max_memory);
  if (!integrators.is_none()) {
    o.integrators = option_text(integrators);
    o.integrators_given = true;
  }
  if (!match.is_none()) {
    o.match = match_words(match);
    o.match_given = true;
  }
  o.vary = vary;
  o.dt = dt.is_none() ? "" : option_text(dt);
  o.layout = layout;
  o.video = video;
  o.frames_dir = frames;
  o.sheet = sheet;
  o.times = times.is_none() ? "" : option_text(times);
  o.still_t = still;
  o.still_out = output;
  o.export_path = export_path;
  o.summary = summary;
  o.look.color = color;
  o.look.color_range = color_range.is_none() ? "" : option_text(color_range);
  o.look.reference = reference;
  o.look.overlay = overlay;
  o.look.overlay_cost = overlay_cost;
  o.look.inset = inset;
  o.look.camera = camera;
  o.look.antialias = antialias;
  if (crf) o.crf = *crf;
  if (preset) o.preset = *preset;
  o.shard = shard;
  o.gl.gl = gl;
  o.table_wanted = true;
  o.frame_rows_wanted = true;
  clip::ComparePlan p;
  std::vector<clip::LaneFrameRow> rows;
  const clip::PipelineReport report = run_interruptible(o, p, rows);
  if (!o.summary.empty()) clip::write_compare_summary(o, p, report);
  py::list lanes;
  const py::object loads = py::module_::import("json").attr("loads");
  for (const clip::JsonObject& lane : clip::compare_lanes_json(p, report)) lanes.append(loads(lane.dump()));
  py::object frame = py::module_::import("pandas").attr("DataFrame")(lanes);
  unresolved_as_booleans(frame);
  frame.attr("attrs")["frames"] = frames_frame(p, rows);
  return frame;
}

}  // namespace

void bind_compare(py::module_& m) {
  py::register_exception<clip::UsageError>(m, "UsageError", PyExc_ValueError);
  py::register_exception<clip::RuntimeFailure>(m, "RuntimeFailure", PyExc_RuntimeError);
  m.def("compare", &compare, py::arg("scene"), py::arg("set") = py::dict(), py::arg("integrators") = py::none(),
        py::arg("match") = py::none(), py::arg("vary") = "", py::arg("dt") = py::none(),
        py::arg("duration") = py::none(), py::arg("layout") = "auto", py::arg("video") = "", py::arg("frames") = "",
        py::arg("sheet") = "", py::arg("times") = py::none(), py::arg("still") = py::none(), py::arg("output") = "",
        py::arg("export") = "", py::arg("summary") = "", py::arg("color") = py::none(),
        py::arg("color_range") = py::none(), py::arg("reference") = "", py::arg("overlay") = py::none(),
        py::arg("overlay_cost") = "", py::arg("inset") = "none", py::arg("width") = py::none(),
        py::arg("height") = py::none(), py::arg("fps") = py::none(), py::arg("gl") = "",
        py::arg("camera") = py::none(), py::arg("antialias") = py::none(), py::arg("crf") = py::none(),
        py::arg("preset") = py::none(), py::arg("shard") = "", py::arg("max_memory") = py::none(),
        "compare(scene, set={}, integrators=None, match=None, vary='', dt=None, duration=None, layout='auto',\n"
        "        video='', frames='', sheet='', times=None, still=None, output='', export='', summary='',\n"
        "        color=None, color_range=None, reference='', overlay=None, overlay_cost='', inset='none',\n"
        "        width=None, height=None, fps=None, gl='', camera=None, antialias=None, crf=None, preset=None,\n"
        "        shard='', max_memory=None) -> pandas.DataFrame\n\n"
        "`clothsim compare SCENE` (a path, or a Scene from load_scene: its file, set=, duration= and dt=) with its options as keywords (--still T -o FILE: still=T, output=FILE;\n"
        "--match error 1e-3: match='error 1e-3'; lists may be Python lists: integrators=['rk4@1e-4',\n"
        "'vbd@1/60:10', 'xpbd@1/60:tol=1e-4']). Writes the files asked for, as the CLI does, and returns a\n"
        "row per lane (and the reference's) with --summary's lane keys (docs/summary.md). Nothing to write\n"
        "is fine here: the table is the result. Its attrs['frames'] is a DataFrame with a row per lane per\n"
        "clip frame (k / fps) and at the end: lane, name, frame_t, run --metrics' columns (step, t, kinetic,\n"
        "..., total_energy, max_strain, ...) and, when a field is measured, its largest value under its\n"
        "name (error, strain or speed); the lanes stop at every frame for it. Runs with the GIL released;\n"
        "Ctrl-C raises KeyboardInterrupt and leaves no partial file. Bad options raise clothsim.UsageError\n"
        "(a ValueError) with the CLI's one-line message.");
}

}  // namespace clothsim::python
