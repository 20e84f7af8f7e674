#include "simulation_binding.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "core/model/diagnostics.h"
#include "core/integrators/integrator_kind.h"
#include "clip/common/cli_common.h"
#include "clip/common/lanes.h"

namespace py = pybind11;

namespace clothsim::python {

Lane parse_lane_argument(const std::string& text, const SceneDef& scene) {
  Lane lane;
  try {
    lane = parse_lane(text);  // the one grammar (scene/lane.h), as every door parses it
  } catch (const LaneError& e) {
    throw py::value_error("lane: " + std::string(e.what()));
  }
  if (!lane.written_step()) {
    lane.dt = scene.dt;
    lane.step_text = step_string(lane.dt);
  }
  return lane;
}

Simulation::Simulation(Scene scene, const std::optional<std::string>& lane)
    : scene_(std::move(scene)) {
  kind_ = scene_.def.integrator;
  dt_ = scene_.def.dt;
  MethodSettings settings = scene_.model->method_defaults();
  if (lane) {
    const Lane parsed = parse_lane_argument(*lane, scene_.def);
    kind_ = parsed.kind;
    dt_ = parsed.dt;
    try {  // the lane's settings (:N, :tol=, the fixed point), as compare runs it
      settings = clip::lane_settings(*scene_.model, parsed);
    } catch (const clip::UsageError& e) {
      throw py::value_error("lane: " + *lane + ": " + e.what());
    }
  }
  run_ = std::make_unique<Run>(*scene_.model, kind_, dt_, settings);
  // Polled before every step; a clock read costs nanoseconds beside a step, and Python's
  // signal check (which takes the GIL) runs only every 0.1 s of wall time.
  auto next_poll = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  run_->set_stop_check([this, next_poll] {
    const auto now = std::chrono::steady_clock::now();
    if (now < *next_poll) return false;
    *next_poll = now + std::chrono::milliseconds(100);
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) interrupted_ = true;
    return interrupted_;
  });
}

void Simulation::step() { advance(true, 0.0); }

void Simulation::run(double until) {
  if (!std::isfinite(until))  // nan ran no step and said nothing; inf would never return
    throw py::value_error("run: until must be a finite time in s, got " +
                          py::str(py::float_(until)).cast<std::string>());
  advance(false, until);
}

std::unique_lock<std::mutex> Simulation::lock() const {
  py::gil_scoped_release release;  // never wait for the mutex holding the GIL its holder may need
  return std::unique_lock<std::mutex>(mutex_);
}

void Simulation::advance(bool one_step, double until) {
  bool was_stopped = false, interrupted = false;
  {
    py::gil_scoped_release release;
    const std::lock_guard<std::mutex> held(mutex_);
    was_stopped = run_->stopped();
    if (!was_stopped) run_->advance_to(one_step ? run_->state().t + dt_ : until);
    interrupted = std::exchange(interrupted_, false);  // said once; the Run stays stopped
  }
  if (interrupted) throw py::error_already_set();  // the KeyboardInterrupt PyErr_CheckSignals set on this thread
  if (was_stopped) throw py::value_error("this Simulation was interrupted: make a new one");
}

namespace {

// A (N, 3) read-only view of columns first .. first + N - 1 of a 3 x B column-major matrix
// (the particles: 0 .. P - 1; the spheres: P .. B - 1): row k is that body's x, y, z, 24 bytes
// apart. Valid until the next step (a step may swap buffers).
py::array body_view(const Eigen::Matrix3Xd& m, int first, int count, const py::object& owner) {
  py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(count), py::ssize_t{3}},
              {py::ssize_t{3 * sizeof(double)}, py::ssize_t{sizeof(double)}}, m.data() + 3 * first, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::dict totals_dict(const RunTotals& t) {
  py::dict d;
  d["steps"] = t.steps;
  d["force_evals"] = t.force_evals;
  d["newton_iterations"] = t.newton_iterations;
  d["cg_iterations"] = t.cg_iterations;
  d["factorizations"] = t.factorizations;
  d["unconverged_steps"] = t.unconverged_steps;
  d["max_residual"] = t.max_residual;
  d["max_strain"] = t.max_strain;
  d["contact_constraints"] = t.contact_constraints;
  d["safety_projections"] = t.safety_projections;
  d["sim_seconds"] = t.sim_seconds;
  d["cpu_seconds"] = t.cpu_seconds;
  return d;
}

// The energies under --metrics' column names, J.
py::dict energies_dict(const Energies& e) {
  py::dict d;
  d["kinetic"] = e.kinetic;
  d["spring_potential"] = e.spring;
  d["gravity_potential"] = e.gravity;
  d["total_energy"] = e.total();
  return d;
}

// A reader of a Simulation that holds it for its thread while it reads (Simulation::lock).
template <class Read>
auto locked(Read read) {
  return [read](const Simulation& s) {
    const auto held = s.lock();
    return read(s);
  };
}

// What a run has to say: diagnostics of the state, totals and verdicts.
void bind_diagnostics(py::class_<Simulation>& c) {
  c.def(
          "energies",
          locked([](const Simulation& s) {
            return energies_dict(compute_energies(s.engine().model(), s.engine().state()));
          }),
          "energies() -> dict: kinetic, spring_potential, gravity_potential, total_energy (J), as --metrics.")
      .def(
          "metrics",
          locked([](const Simulation& s) {
            const FrameMetrics f = s.engine().metrics();
            py::dict d;
            d["step"] = f.step;
            d["t"] = f.t;
            d.attr("update")(energies_dict(f.energies));
            d["max_strain"] = f.max_strain;
            d["contacts"] = f.contacts;
            d["force_evals"] = f.force_evals;
            d["newton_iterations"] = f.newton_iterations;
            d["cg_iterations"] = f.cg_iterations;
            d["residual"] = f.residual;
            d["converged"] = f.converged;
            return d;
          }),
          "metrics() -> dict: the row `run --metrics` writes for the current state.")
      .def_property_readonly("max_strain", locked([](const Simulation& s) { return s.engine().metrics().max_strain; }),
                             "Largest spring strain |l/l0 - 1| of the current state.")
      .def_property_readonly("totals", locked([](const Simulation& s) { return totals_dict(s.engine().totals()); }),
                             "Running totals: steps, force_evals, Newton/CG work, unconverged_steps, CPU s...")
      .def_property_readonly("diverged", locked([](const Simulation& s) { return s.engine().diverged(); }),
                             "Whether the run diverged (run's exit 3); .divergence says when and why.")
      .def_property_readonly(
          "divergence",
          locked([](const Simulation& s) -> py::object {
            const auto& d = s.engine().divergence();
            if (!d) return py::none();
            py::dict out;
            out["step"] = d->step;
            out["t"] = d->t;
            out["reason"] = d->reason;
            char t[32];  // the line `run` prints (after "clothsim: ")
            std::snprintf(t, sizeof t, "%.6g", d->t);
            out["message"] = s.scene().def.source + ": diverged at step " + std::to_string(d->step) + ", t = " + t +
                             " s: " + d->reason;
            return std::move(out);
          }),
          "None, or {step, t, reason, message} where the run diverged.")
      .def_property_readonly("not_converged",
                             locked([](const Simulation& s) { return s.engine().totals().unconverged_steps; }),
                             "Implicit steps that ended above their Newton tolerance (run --strict's exit 4 when > 0).")
      .def_property_readonly(
          "wrong",
          locked([](const Simulation& s) -> py::object {
            const auto& w = s.engine().totals().wrong;
            if (!w) return py::none();
            py::dict out;
            out["step"] = w->step;
            out["t"] = w->t;
            out["reason"] = w->reason;
            return std::move(out);
          }),
          "None, or {step, t, reason}: the first WRONG verdict (energy made with no work done, or\n"
          "strain past its bound; run --strict's exit 5). The run goes on, as run's does.");
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<Simulation> c(m, "Simulation",
                         "Simulation(scene, lane=None)\n\n"
                         "One scene stepped with one integrator at one step, as `clothsim run` steps it:\n"
                         "lane 'rk4@4e-4' (NAME@STEP, the step a number or a fraction like 1/2500),\n"
                         "'rk4' (the scene's step) or None (the scene's integrator and step); ':N' sets the\n"
                         "iterations ('vbd@1/60:10', 'implicit_euler@1/60:1'), ':tol=T' a residual to stop each\n"
                         "step on ('xpbd@1/60:tol=1e-4'), as compare's lanes and `run --iterations` do.");
  c.def(py::init<Scene, const std::optional<std::string>&>(), py::arg("scene"), py::arg("lane") = py::none())
      .def("step", &Simulation::step, "Takes one step of dt.")
      .def("run", &Simulation::run, py::arg("until"),
           "run(until) -> None\n\nSteps until t >= until, in C++ with the GIL released (no Python per step).\n"
           "Stops at divergence (see .diverged). Ctrl-C raises KeyboardInterrupt within 0.1 s. until must be\n"
           "finite (ValueError). Threads may share a Simulation: one steps or reads it at a time, a\n"
           "second run() waiting for the first and going on from where it ends.")
      .def_property_readonly("t", locked([](const Simulation& s) { return s.engine().state().t; }),
                             "Simulated time, s.")
      .def_property_readonly("steps", locked([](const Simulation& s) { return s.engine().state().step; }))
      .def_property_readonly("dt", &Simulation::dt, "The step, s.")
      // As run --metrics names it: the course's fixed point is implicit_euler_fixed_point.
      .def_property_readonly("integrator", [](const Simulation& s) { return method_name(s.kind(), s.engine().settings().implicit); })
      .def_property_readonly(
          "positions",
          [](py::object self) {
            const Simulation& s = self.cast<const Simulation&>();
            const auto held = s.lock();
            return body_view(s.engine().state().x, 0, s.engine().model().num_particles, self);
          },
          "Particle positions, m: a read-only numpy (P, 3) float64 view of the state, no copy.\n"
          "It shows the state as it is now; take it again after stepping.")
      .def_property_readonly(
          "velocities",
          [](py::object self) {
            const Simulation& s = self.cast<const Simulation&>();
            const auto held = s.lock();
            return body_view(s.engine().state().v, 0, s.engine().model().num_particles, self);
          },
          "Particle velocities, m/s: a read-only numpy (P, 3) float64 view, as .positions.")
      .def_property_readonly(
          "spheres",
          [](py::object self) {
            const Simulation& s = self.cast<const Simulation&>();
            const auto held = s.lock();
            const Model& model = s.engine().model();
            // Spheres are bodies P .. P + S - 1 of the state (a kinematic one moved there by the
            // timeline each step): the centres the renderer draws and --export writes.
            return body_view(s.engine().state().x, model.num_particles, model.num_spheres, self);
          },
          "Sphere centres at the current t, m: a read-only numpy (S, 3) float64 view of the state, as\n"
          ".positions (a kinematic sphere where its scripted motion has taken it).")
      .def_property_readonly(
          "sphere_radii",
          [](const Simulation& s) {
            const std::vector<double>& r = s.engine().model().sphere_radius;
            return py::array_t<double>(static_cast<py::ssize_t>(r.size()), r.data());  // a copy: (S,)
          },
          "Sphere radii, m: numpy (S,) float64, in .spheres' order.")
      .def("__repr__", [](const Simulation& s) {
        const auto held = s.lock();
        return "<clothsim.Simulation " + s.scene().def.name + " " + std::string(integrator_name(s.kind())) + "@" +
               py::str(py::float_(s.dt())).cast<std::string>() + " t=" +
               py::str(py::float_(s.engine().state().t)).cast<std::string>() + ">";
      });
  bind_diagnostics(c);
}

}  // namespace clothsim::python
