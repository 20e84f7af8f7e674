// clothsim.Simulation: one scene stepped with one integrator at one step (a `run` lane), the
// same Run (core/simulation.h) `clothsim run` steps, so its states are the CLI's bit for bit.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>
#include <optional>

#include "scene/lane.h"
#include "scene_binding.h"
#include "core/run/simulation.h"

namespace clothsim::python {

// One thread at a time steps or reads a Simulation: two threads in run() shared one Run's
// state and workspace and crashed the interpreter (issue #51). Every entry takes lock(), which
// waits with the GIL released, so a thread stepping (it takes the GIL to poll signals) is
// never blocked by one waiting; a second run() waits for the first and then goes on from
// where it left the state.
class Simulation {
 public:
  Simulation(Scene scene, const std::optional<std::string>& lane);
  // One step of dt.
  void step();
  // Steps until t >= until (the CLI's targets are reached the same way), with the GIL released;
  // polls Python's signals every 0.1 s of wall time (KeyboardInterrupt). ValueError for an
  // `until` that is not a number (nan ran no step and said nothing).
  void run(double until);
  // This Simulation for the calling thread alone, until the lock is dropped. Call with the GIL held.
  std::unique_lock<std::mutex> lock() const;
  const Run& engine() const { return *run_; }
  const Scene& scene() const { return scene_; }
  // Whether it was made from `scene`: it runs on the scene's own model (the lane's settings
  // ride in its Run, not in a model of its own).
  bool of_scene(const Scene& scene) const { return scene_.model == scene.model; }
  IntegratorKind kind() const { return kind_; }
  double dt() const { return dt_; }

 private:
  void advance(bool one_step, double until);

  Scene scene_;
  IntegratorKind kind_;
  double dt_;
  std::unique_ptr<Run> run_;
  bool interrupted_ = false;
  mutable std::mutex mutex_;
};

// Simulation(lane=...): the lane grammar's value (scene/lane.h), ValueError "lane: ..." when it
// refuses; a lane without @STEP at the scene's step.
Lane parse_lane_argument(const std::string& text, const SceneDef& scene);

void bind_simulation(pybind11::module_& m);

}  // namespace clothsim::python
