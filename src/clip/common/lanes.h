// Lanes: what a comparison runs side by side. A lane is one simulation of the scene with one
// method at one step (scene/lane.h: the value, its grammar and its one parser); this is the
// command line's door to it: `--integrators rk4@1e-4,rk4@4e-4,implicit_euler@1/60` is three
// lanes, two of them RK4, and the lanes without @STEP take --dt or the scene's step.
// Every function throws UsageError with a one-line message naming the option.
#pragma once

#include <string>
#include <vector>

#include "core/model/model.h"
#include "scene/lane.h"

namespace clothsim::clip {

// implicit_euler lanes of a scene with `implicit: {solver: fixed_point}` run the fixed point:
// marked as such (its iterations kept), so tables, CSVs and plots name it implicit_euler_fixed_point
// and never mistake it for backward Euler.
void follow_scene_solver(std::vector<Lane>& lanes, const ImplicitDef& implicit);

// --integrators: the lane grammar's list (scene/lane.h, "course" among the items). An item
// without @STEP takes its step from --dt ("S", "name=S,...", or both, as before the lanes had
// steps; name=S applies to that integrator's lanes without @STEP, implicit_euler=S to the fixed
// point's too), else the scene's dt (step_from Option or Scene). The same integrator may appear at several
// steps; the same lane twice is an error.
std::vector<Lane> parse_lanes(const std::string& integrators, const std::string& dt, double scene_dt);

// --integrators of a study that chooses the steps itself (bench sweeps them, stability searches
// them): the same lanes, an @STEP refused with UsageError "--integrators: ITEM: <why_no_step>".
std::vector<Lane> parse_study_lanes(const std::string& integrators, const std::string& why_no_step);

// A study that steps at fixed steps refuses an adaptive pair's lane (bs3, dopri5, rkf78: their
// tolerance chooses the steps): UsageError "--integrators: 'dopri5': <why>".
void refuse_adaptive_lanes(const std::vector<Lane>& lanes, const std::string& why);

// The smallest step of the lanes (not empty): what the reference's default step is a quarter
// of (and, where that is above RK4's stable step, divided into whole steps: picture_options.h).
double smallest_step(const std::vector<Lane>& lanes);

// --reference NAME[@STEP]; "" is RK4 at a quarter of the smallest lane step, the error
// colouring's default. Without @STEP, a quarter of the smallest lane step too.
Lane parse_reference(const std::string& text, const std::vector<Lane>& lanes);

// Directory names for --frames, one per lane: the integrator's name when it is the only
// lane of that integrator (DIR/rk4, as before lanes had steps), else name@step with '/'
// spelled '_' (DIR/rk4@1e-4, DIR/implicit_euler@1_60).
std::vector<std::string> lane_directories(const std::vector<Lane>& lanes);

// The method settings a lane runs with on `base` (core/base/method_settings.h): the model's
// own (its scene's blocks), then the lane's items over them: the course's fixed point, `:N`,
// `:tol=` (its cap `:N`, else kToleranceCap), `:rtol=`/`:atol=`, the method's own parameters.
// The lane runs on `base` itself with them: a Run carries them, no copy of the model does.
// UsageError "--integrators: collision.model: barrier: ..." for a method the scene's contact
// model refuses.
MethodSettings lane_settings(const Model& base, const Lane& lane);

// The lane grammar's refusal (scene/lane.h's LaneError) as the usage error of `option`
// ("--integrators: unknown integrator 'rk9' (...)"); an empty option keeps the message whole.
[[noreturn]] void refuse_lane(const std::string& option, const LaneError& e);

// An iteration count option (--iterations, --states...): scene/lane.h's parse_iteration_count,
// its refusal a UsageError "OPTION: 'x' is not a whole number from 1 to 1000000".
int parse_iteration_option(const std::string& text, const std::string& option);

// Sets the iterations `kind` runs with in `settings` (see Lane::iterations); UsageError naming
// `what` for an integrator without iterations (the explicit family).
void set_iterations(MethodSettings& settings, IntegratorKind kind, bool fixed_point, int iterations,
                    const std::string& what);

// Sets an iterative solver's residual tolerance in `settings`, with `cap` its iteration cap.
void set_tolerance(MethodSettings& settings, IntegratorKind kind, double tolerance, int cap);

}  // namespace clothsim::clip
