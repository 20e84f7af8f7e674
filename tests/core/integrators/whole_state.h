// What every integrator owes the whole state, checked the same way for each (the methods
// differ only in how a dynamic sphere's free fall is discretised):
//  - a kinematic sphere (inverse mass 0) moves at its velocity exactly: x(t) = x0 + t v0;
//  - a pinned particle does not move;
//  - a dynamic sphere is a body like any other: under gravity alone it falls as the
//    method discretises y'' = -g. After n steps of h from rest, y0 - y_n = g h^2 c(n) with
//    c = n(n-1)/2 for forward Euler, n(n+1)/2 for symplectic and backward Euler (both take
//    the position step with v_{n+1}), and the exact n^2/2 for midpoint and RK4.
// The scene is drape.yaml shrunk to 5 x 5 with two spheres far from the cloth (no contact),
// so the cloth's springs and the spheres are integrated in the same step.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/model/model.h"
#include "core/run/simulation.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::testing {

inline Model sheet_with_two_spheres(const std::vector<std::string>& extra = {}) {
  std::vector<std::string> overrides{
      "cloth.particles=[5, 5]",
      "spheres=[{center: [10, 0, 0], radius: 0.5, kinematic: true, velocity: [1, 0.5, -2]},"
      " {center: [-10, 0.5, 0], radius: 0.5, kinematic: false, mass: 3}]",
      "events=[]",
  };
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", overrides));
}

// fall_steps_offset: -1 forward Euler, +1 symplectic and backward Euler, 0 midpoint and RK4.
// rel_tol: 1e-9 for the explicit family (rounding over 100 steps of a 0.5 mm fall); an
// iterative solve is exact to its tolerance only.
inline void expect_whole_state_integrated(IntegratorKind kind, double fall_steps_offset,
                                          double rel_tol = 1e-9,
                                          const std::vector<std::string>& extra = {}) {
  const Model model = sheet_with_two_spheres(extra);
  const int kinematic = model.sphere_body(0), dynamic = model.sphere_body(1);
  ASSERT_EQ(model.initial_inv_mass[kinematic], 0.0);
  ASSERT_GT(model.initial_inv_mass[dynamic], 0.0);
  State state = initial_state(model);
  const State start = state;
  Workspace ws;
  const double h = 1e-4;  // the drape scene's step: stable for every method on its cloth
  const int n = 100;
  for (int i = 0; i < n; ++i) {
    const StepReport r = step(model, state, kind, h, ws);
    ASSERT_EQ(r.contacts.total(), 0) << "the spheres must stay clear of everything";
  }
  const double t = n * h;
  EXPECT_LT((state.x.col(kinematic) - (start.x.col(kinematic) + t * start.v.col(kinematic))).norm(), 1e-12);
  EXPECT_LT((state.v.col(kinematic) - start.v.col(kinematic)).norm(), 1e-15);
  for (int p = 0; p < model.num_particles; ++p) {
    if (model.initial_inv_mass[p] != 0.0) continue;
    EXPECT_EQ(state.x.col(p), start.x.col(p)) << "pinned particle " << p << " moved";
  }
  const double g = -model.gravity.y();
  const double fall = start.x(1, dynamic) - state.x(1, dynamic);
  const double expected = g * h * h * (0.5 * n * n + fall_steps_offset * 0.5 * n);
  EXPECT_NEAR(fall, expected, rel_tol * expected) << integrator_name(kind);
  EXPECT_NEAR(state.v(1, dynamic), -g * t, rel_tol * g * t);
  // The cloth between them did move: the step acted on particles and spheres together.
  EXPECT_GT((state.x.leftCols(model.num_particles) - start.x.leftCols(model.num_particles)).norm(), 0.0);
}

// Every step (of a scene with cloth and both kinds of sphere) costs exactly `evals` force
// evaluations, and nominal_force_evals() says so too.
inline void expect_force_evals_per_step(IntegratorKind kind, int evals) {
  const Model model = sheet_with_two_spheres();
  State state = initial_state(model);
  Workspace ws;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(step(model, state, kind, 1e-4, ws).stats.force_evals, evals);
  EXPECT_EQ(nominal_force_evals(kind), evals);
}

// stiff.yaml is run at a step four to five times every explicit method's limit: the method
// must be stopped by divergence detection early, not run to the end.
inline void expect_diverges_early_on_the_stiff_scene(IntegratorKind kind) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml"));
  clothsim::Run run(model, kind, model.dt);
  EXPECT_FALSE(run.advance_to(model.duration)) << integrator_name(kind);
  ASSERT_TRUE(run.diverged()) << integrator_name(kind);
  EXPECT_LT(run.divergence()->t, 0.25 * model.duration) << integrator_name(kind);
}

}  // namespace clothsim::testing
