// How a method's cost grows as the sheet is refined (issue #37): the same scene at sides
// N = 32, 64, 128, ... (cloth.particles = [N, N]) with the sheet's size and total mass fixed,
// each lane run to the same simulated time, reporting CPU per simulated second, Newton and
// linear iterations, and memory. The fitted exponent p of cost ~ particles^p says it in one
// number: 1 is linear cost, block-Jacobi PCG's textbook growth is about 1.5 per Newton solve.
//
// Total mass: the first size keeps the scene's cloth.particle_mass, and each later size
// carries particle_mass x (first / N)^2, so `--scale 32,64,128,256` on a 1 kg scene is the
// issue's refinement (particle mass (32/N)^2). Spring stiffness per spring is the scene's.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "study.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "core/run/simulation.h"
#include "scene/scene_def.h"

namespace clothsim::analysis {

struct ScaleLane {
  std::string name;  // as the CSV spells it: "implicit_euler@1/60"
  IntegratorKind kind{};
  double dt = 0.0;   // s
};

// One scene per size, with the size's particle_mass (the first keeps the scene's).
struct ScaleScene {
  int side = 0;
  SceneDef scene;
};

struct ScaleSpec {
  std::vector<ScaleScene> sizes;  // smallest first
  std::vector<ScaleLane> lanes;
  double duration = 0.0;          // s simulated by every run
  // The settings lane `lane` runs with on a size's model (its own solver settings, as
  // compare's lanes); null: the model's own.
  std::function<MethodSettings(const Model& model, std::size_t lane)> lane_settings;
};

struct ScalePoint {
  std::size_t lane = 0;
  int side = 0;
  int particles = 0;
  double particle_mass = 0.0;  // kg
  RunTotals totals;
  bool finished = false;       // reached the duration (false: diverged or stopped)
  std::string reason;          // why not
  double simulated = 0.0;      // s actually simulated
  double memory_estimate = 0.0;  // bytes: model + one run (scene/memory_estimate.h)
  double peak_rss = 0.0;         // bytes: the process's peak resident set after this run

  double cpu_per_simulated_second() const { return simulated > 0 ? totals.cpu_seconds / simulated : 0.0; }
  double newton_per_step() const;
  double linear_per_newton() const;  // CG iterations per Newton iteration
};

// `sides` (each >= 2, increasing) of the scene at `path` with the user's --set first.
// Throws StudyError for bad sides, SceneError for a rejected scene.
std::vector<ScaleScene> scale_scenes(const std::string& path, const std::vector<std::string>& sets,
                                     const std::vector<int>& sides);

// Runs every lane at every size, smallest size first (so peak_rss grows with the sizes);
// `done` is told of each point as it finishes. Stops early when hooks.stop says so.
std::vector<ScalePoint> scale_study(const ScaleSpec& spec, const StudyHooks& hooks,
                                    const std::function<void(const ScalePoint&)>& done = {});

// The least-squares slope of log(CPU per simulated second) against log(particles) over the
// lane's finished points; NaN with fewer than two.
double scale_exponent(const std::vector<ScalePoint>& points, std::size_t lane);

// The CSV: a header and one row per point, columns as scale_csv_header() names them.
std::string scale_csv_header();
std::string scale_csv_row(const ScalePoint& p, const std::vector<ScaleLane>& lanes, double duration);

}  // namespace clothsim::analysis
