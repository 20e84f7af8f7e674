// Engine -> renderer: fill a RenderFrame from the model and state (positions, normals,
// spheres, ground, camera, overlay text). The only place the engine meets rendering.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "diagnostics.h"
#include "model.h"
#include "render_frame.h"
#include "state.h"

namespace clothsim {

struct SnapshotText {
  std::vector<std::string> lines;  // overlay lines (see overlay_lines() for the standard set)
  std::string banner;              // e.g. "DIVERGED at t = 1.234 s"
};

RenderFrame make_render_frame(const Model& model, const State& state, const SnapshotText& text);

// Marks a frame of a run's last finite state (Run::last_finite_state) as the frozen frame:
// the red banner "DIVERGED at t = ... s (step N)" with the time as `run` prints it, and a last
// overlay line with the reason. What `run` and `compare` show from the moment a run diverges.
void mark_diverged(RenderFrame& frame, const Divergence& divergence);

// Marks a frame of a run whose implicit steps missed their Newton tolerance `steps` times so
// far (steps > 0): the red banner "NOT CONVERGED (N steps)", "(1 step)" for one.
void mark_not_converged(RenderFrame& frame, std::int64_t steps);

// The overlay of a run's picture: the scene, the lane (integrator_label) and the time
// (overlay_time_line); `run` adds its cost beneath (tools/cli/frame_pipeline.h, lane_overlay),
// and a compare tile starts at the time, its lane being the grid's label. These functions are
// where those lines are written, for every picture that has them.
std::vector<std::string> overlay_lines(const Model& model, const std::string& lane_label, double t);
// The same for `kind` at step dt, written %.3g (what a scene's own run shows for common steps).
std::vector<std::string> overlay_lines(const Model& model, IntegratorKind kind, double dt, double t);
// "rk4  dt = 1e-4 s": an integrator (`name`) at a step as written (`step`, s).
std::string integrator_label(std::string_view name, std::string_view step);
// "t = 1.500 s".
std::string overlay_time_line(double t);

}  // namespace clothsim
