// Lanes: what a comparison runs side by side. A lane is one simulation of the scene with one
// integrator at one step (and, for the course's "implicit", its one-iteration fixed point):
// `--integrators rk4@1e-4,rk4@4e-4,implicit_euler@1/60` is three lanes, two of them RK4.
// Every function throws UsageError with a one-line message naming the option.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/integrators/integrator_kind.h"
#include "core/model.h"

namespace clothsim::clip {

struct LaneSpec {
  IntegratorKind kind{};
  double dt = 0.0;
  std::string step_text;                // the step as the user wrote it ("1/60", "1e-4"), else %g
  bool fixed_point = false;  // the course's "implicit": implicit_euler as one fixed-point
                             // iteration (`implicit: {solver: fixed_point, iterations: 1}`)
  int iterations = 0;  // `:N`: the solver's iterations (implicit_euler: its Newton cap; the
                       // fixed point: its iterations); 0 = as the scene sets them
  double tolerance = 0.0;  // `:tol=T` (xpbd, projective_dynamics, vbd): stop each step on the
                           // residual, `:N` (else kToleranceCap) then a cap; 0 = as the scene sets

  // "rk4", "implicit_euler (fixed point)", "vbd:10", "implicit_euler:1 (Baraff & Witkin)"
  std::string name() const;
  std::string label() const;  // name and step: "rk4  dt = 1e-4 s"
  // As --integrators spells it, and parses back to this lane: "rk4@1e-4",
  // "implicit_euler_fixed_point@0.0001", "xpbd@1/600:1" (--summary's "lane").
  std::string spelling() const;
  // The spelling without a step, for the studies that choose the steps themselves (bench,
  // stability): "rk4", "implicit_euler_fixed_point", "xpbd:10".
  std::string stepless_spelling() const;
  // implicit_euler's Newton capped at :N by the user: its steps stop at N iterations on purpose,
  // so a residual above tolerance is the method asked for, not a stalled solve.
  bool newton_capped() const {
    return iterations > 0 && integrator_info(kind).iterations == IterationControl::Newton && !fixed_point;
  }
};

// implicit_euler lanes of a scene with `implicit: {solver: fixed_point}` run the fixed point:
// marked as such (its iterations kept), so tables, CSVs and plots name it implicit_euler_fixed_point
// and never mistake it for backward Euler.
void follow_scene_solver(std::vector<LaneSpec>& lanes, const ImplicitDef& implicit);

// The iteration cap of a lane given `:tol=T` without `:N`.
inline constexpr int kToleranceCap = 1000;

// --integrators: "course" (the course's four: explicit Euler, the one-iteration fixed-point
// "implicit", midpoint, RK4) or NAME[@STEP][:N],... with N the lane's iterations (an
// iterative solver's, implicit_euler's Newton cap, the fixed point's count) and STEP a number or a fraction, NAME an
// integrator or implicit_euler_fixed_point (the course's "implicit" alone). An item without
// @STEP takes its step from --dt ("S", "name=S,...", or both, as before the lanes had steps;
// name=S applies to that integrator's lanes without @STEP, implicit_euler=S to the fixed point's
// too), else the scene's dt. The same integrator may appear at several steps; the same lane
// twice is an error. --reference takes the integrators only.
std::vector<LaneSpec> parse_lanes(const std::string& integrators, const std::string& dt, double scene_dt);

// --integrators of a study that chooses the steps itself (bench sweeps them, stability searches
// them): the same lanes, an @STEP refused with UsageError "--integrators: ITEM: <why_no_step>".
std::vector<LaneSpec> parse_study_lanes(const std::string& integrators, const std::string& why_no_step);

// The smallest step of the lanes (not empty): what the reference's default step is a quarter
// of (and, where that is above RK4's stable step, divided into whole steps: picture_options.h).
double smallest_step(const std::vector<LaneSpec>& lanes);

// --reference NAME[@STEP]; "" is RK4 at a quarter of the smallest lane step, the error
// colouring's default. Without @STEP, a quarter of the smallest lane step too.
LaneSpec parse_reference(const std::string& text, const std::vector<LaneSpec>& lanes);

// Directory names for --frames, one per lane: the integrator's name when it is the only
// lane of that integrator (DIR/rk4, as before lanes had steps), else name@step with '/'
// spelled '_' (DIR/rk4@1e-4, DIR/implicit_euler@1_60).
std::vector<std::string> lane_directories(const std::vector<LaneSpec>& lanes);

// The model a lane runs: `base` itself, or a copy with the course's implicit settings (the
// fixed-point lane) and the lane's iterations (`storage` holds the copy).
const Model& lane_model(const Model& base, const LaneSpec& lane, std::optional<Model>& storage);

// An iteration count as typed (`:N`, --iterations): a whole number from 1 to
// kMaxSolverIterations, else UsageError naming `what`.
int parse_iteration_count(const std::string& text, const std::string& what);

// Sets the iterations `kind` runs with in `model` (see LaneSpec::iterations); UsageError naming
// `what` for an integrator without iterations (the explicit family).
void set_iterations(Model& model, IntegratorKind kind, bool fixed_point, int iterations,
                    const std::string& what);

// Sets an iterative solver's residual tolerance in `model`, with `cap` its iteration cap.
void set_tolerance(Model& model, IntegratorKind kind, double tolerance, int cap);

// "%g" of a step, the way labels and messages write it.
std::string step_string(double dt);

}  // namespace clothsim::clip
