// Projective dynamics' factors for the solver kernels' tests: the drape's global matrix
// (corners pinned, h = 1/60 s) at a chosen size, factored as a PD step factors it.
#pragma once

#include <string>

#include "core/integrators/integrator.h"
#include "core/solvers/solver_cache.h"
#include "core/model/state.h"
#include "test_support.h"

namespace clothsim::testing {

struct DrapeFactor {
  explicit DrapeFactor(int n)
      : model(build_model(load_scene(scene_path("drape.yaml"), {"cloth.particles=[" + std::to_string(n) + "," +
                                                                std::to_string(n) + "]"}))) {
    State s = initial_state(model);
    integrate(IntegratorKind::ProjectiveDynamics, model, s, 1.0 / 60.0, ws);
  }
  const PdFactor& pd() { return solver_cache(ws).pd; }

  Model model;
  Workspace ws;
};

}  // namespace clothsim::testing
