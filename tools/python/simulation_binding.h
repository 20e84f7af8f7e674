// clothsim.Simulation: one scene stepped with one integrator at one step (a `run` lane), the
// same Run (core/simulation.h) `clothsim run` steps, so its states are the CLI's bit for bit.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <optional>

#include "scene_binding.h"
#include "core/simulation.h"

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

// "rk4@4e-4", "rk4@1/2500", "rk4" (the scene's step), None (the scene's integrator and step).
void parse_lane(const std::string& lane, const SceneDef& scene, IntegratorKind& kind, double& dt);

void bind_simulation(pybind11::module_& m);

}  // namespace clothsim::python
