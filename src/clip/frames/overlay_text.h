// The words on a lane's picture: its overlay lines (scene, lane, time), the lane's label, and
// the banners of a run's results (DIVERGED, NOT CONVERGED). The engine hands over geometry
// (snapshot.h) and numbers (a Divergence, a count of missed steps); what a picture says about
// them is presentation, written here for every picture that has it: `run`'s frames, compare's
// tiles (frame_pipeline.h), the renderer benchmark.
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/diagnostics.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "view/render_frame.h"

namespace clothsim::clip {

// The overlay of a run's picture: the scene, the lane (clip/common/lanes.h's integrator_label) and the time
// (overlay_time_line); `run` adds its cost beneath (frame_pipeline.h, lane_overlay), and a
// compare tile starts at the time, its lane being the grid's label.
std::vector<std::string> overlay_lines(const Model& model, const std::string& lane_label, double t);
// The same for `kind` at step dt, written %.3g (what a scene's own run shows for common steps).
std::vector<std::string> overlay_lines(const Model& model, IntegratorKind kind, double dt, double t);
// "t = 1.500 s".
std::string overlay_time_line(double t);

// Marks a frame of a run's last finite state (Run::last_finite_state) as the frozen frame:
// the red banner "DIVERGED at t = ... s (step N)" with the time as `run` prints it, and a last
// overlay line with the reason. What `run` and `compare` show from the moment a run diverges.
// The banner's phrases are "DIVERGED", "at t = ... s" and "(step N)": a narrow tile shows them
// on two lines, and one too narrow for that leaves the step off (render_frame.h).
// With `predicted_limit` (analysis::predicted_limit for the lane's method and model, s; NaN:
// not given) a last line says the step that would have been stable (stable_step_line).
void mark_diverged(RenderFrame& frame, const Divergence& divergence,
                   double predicted_limit = std::numeric_limits<double>::quiet_NaN());

// The step the scene's stiffness estimate predicts stable for a lane that diverged: "stable
// below ~1.5e-04 s (estimate)" (the estimate is a lower bound on the true limit, about 2.4x
// low on the drape: docs/integrators.md), "no stable step (estimate)" where it predicts none
// (undamped explicit Euler, midpoint), "" where it predicts no limit (infinity) or none is given.
std::string stable_step_line(double predicted_limit);

// What a lane that diverged says where its picture is not repeated (a contact sheet's row
// after its held cell): "DIVERGED at t = 0.0212 s (step 53)", the reason, and the stable step
// (stable_step_line) when there is one to say.
std::vector<std::string> diverged_caption(const Divergence& divergence, double predicted_limit);

// Marks a frame of a run whose implicit steps missed their Newton tolerance `steps` times so
// far (steps > 0): the red banner "NOT CONVERGED (N steps)", "(1 step)" for one.
void mark_not_converged(RenderFrame& frame, std::int64_t steps);

// Marks a frame of a lane judged implausible (plausibility.h): the red banner "WRONG" over the
// verdict's phrases (`verdict` as implausible() gives it, "WRONG: a, b"), one per line.
void mark_wrong(RenderFrame& frame, const std::string& verdict);

// The cost line of a picture: spring-pass equivalents (core/work_units.h) per simulated
// second, the same on every run of a command, and with `cpu` the measured CPU time beside
// them ("10.0k passes/sim s  71 ms cpu/sim s"); at t = 0 the work so far.
std::string cost_line(double passes, double cpu_seconds, double t, bool cpu);

}  // namespace clothsim::clip
