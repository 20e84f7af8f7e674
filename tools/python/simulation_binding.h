// clothsim.Simulation: one scene stepped with one integrator at one step (a `run` lane), the
// same Run (core/simulation.h) `clothsim run` steps, so its states are the CLI's bit for bit.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <optional>

#include "scene/lane.h"
#include "scene_binding.h"
#include "core/run/simulation.h"

namespace clothsim::python {

class Simulation {
 public:
  Simulation(Scene scene, const std::optional<std::string>& lane);
  // One step of dt.
  void step();
  // Steps until t >= until (the CLI's targets are reached the same way), with the GIL released;
  // polls Python's signals every 0.1 s of wall time (KeyboardInterrupt).
  void run(double until);
  const Run& engine() const { return *run_; }
  const Scene& scene() const { return scene_; }
  IntegratorKind kind() const { return kind_; }
  double dt() const { return dt_; }

 private:
  Scene scene_;
  IntegratorKind kind_;
  double dt_;
  std::unique_ptr<Run> run_;
  bool interrupted_ = false;
};

// Simulation(lane=...): the lane grammar's value (scene/lane.h), ValueError "lane: ..." when it
// refuses; a lane without @STEP at the scene's step.
Lane parse_lane_argument(const std::string& text, const SceneDef& scene);

void bind_simulation(pybind11::module_& m);

}  // namespace clothsim::python
