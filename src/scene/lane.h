// A lane: one method at one step with its settings, the value every door passes down. One
// grammar, parsed here and nowhere else, by `run --integrator`, `compare/bench/stability
// --integrators`, the scene's `integrator:` key and Python's Simulation(lane=...):
//
//     NAME[@STEP][:ITEM]...      ITEM = N (iterations) | KEY=VALUE
//
//   rk4@2e-4              RK4 at 2e-4 s
//   vbd:10                VBD, 10 iterations a step, at the step the door supplies (the scene's)
//   xpbd@1/60:5           XPBD at one step a frame, 5 iterations
//   vbd@1/60:tol=1e-4     VBD stopping each step on its relative residual, 1000 iterations its cap
//   implicit_euler@1/60:1 backward Euler's single linearised step (Baraff & Witkin 1998)
//   implicit_euler_fixed_point   the course's "implicit": backward Euler as one fixed-point iteration
//
// NAME is an integrator of the registry or implicit_euler_fixed_point; STEP a number or a
// fraction (s); N a whole number (the solver's iterations: an iterative solver's sweeps,
// implicit_euler's Newton cap, the fixed point's count); KEY=VALUE a method's own parameter
// (tol= for xpbd, projective_dynamics and vbd: a residual; tol=, rtol=, atol= for the adaptive
// pairs bs3, dopri5 and rkf78, whose @STEP is their first trial step: `dopri5:tol=1e-8`;
// a method's own: beta= and gamma= for newmark, rho= for generalized_alpha).
// Spaces around the pieces are ignored; a space inside a number is not ("1/ 60" is refused
// everywhere).
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/integrators/integrator_kind.h"

namespace clothsim {

struct SceneDef;

// Where a lane's step came from: what summaries say, and what --match may change (a lane whose
// step the user wrote is never re-stepped).
enum class StepFrom {
  Written,       // @STEP in the lane
  Option,        // the door's own option for it (--dt)
  Scene,         // the scene's dt (a lane without @STEP, until its door says otherwise)
  MatchedCost,   // compare --match cost chose it
  MatchedError,  // compare --match error chose it
};

struct Lane {
  IntegratorKind kind{};
  double dt = 0.0;           // s; 0 until the door resolves a lane without @STEP
  std::string step_text;     // the step as written ("1/60", "1e-4"), else step_string(dt)
  bool fixed_point = false;  // the course's "implicit": implicit_euler as one fixed-point
                             // iteration (`implicit: {solver: fixed_point, iterations: 1}`)
  StepFrom step_from = StepFrom::Scene;
  int iterations = 0;        // `:N`; 0 = as the scene sets them
  double tolerance = 0.0;    // `:tol=T` (xpbd, projective_dynamics, vbd): stop each step on the
                             // residual, `:N` (else kToleranceCap) then a cap; 0 = as the scene sets
  // A method's own parameters, in the order written (`:beta=0.3:gamma=0.6` for newmark, `:rho=`
  // for generalized_alpha: its registry row's `parameters`, core/integrators/method_param.h).
  std::vector<std::pair<std::string, double>> params;
  double rtol = 0.0, atol = 0.0;  // an adaptive pair's (bs3, dopri5, rkf78) error control: `:tol=T`
                                  // sets both, `:rtol=`/`:atol=` one; 0 = as the scene sets

  bool written_step() const { return step_from == StepFrom::Written; }
  // A lane whose step --match may choose: one the user gave no step for (neither @STEP nor --dt),
  // of a method that steps at a step (an adaptive pair's tolerance chooses its own).
  bool free_step() const { return step_from == StepFrom::Scene && !integrator_info(kind).adaptive; }
  // "rk4", "implicit_euler (fixed point)", "vbd:10", "implicit_euler:1 (Baraff & Witkin)"
  std::string name() const;
  std::string label() const;  // name and step: "rk4  dt = 1e-4 s"
  // As the grammar spells it, and parses back to this lane: "rk4@1e-4",
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
  // The grid a lane's states land on, for what stands in at its times (clip/reference): its step
  // (Run stops at the first step at or past a target), or 0 for an adaptive pair, which lands
  // on every target exactly.
  double landing_grid() const { return integrator_info(kind).adaptive ? 0.0 : dt; }
  // The same method at the same step with the same settings (how it was written aside).
  bool same_as(const Lane& other) const;
};

// What the grammar refuses, in words that follow the door's own prefix ("--integrators: ",
// "integrator: ", "lane: "): "unknown integrator 'rk9' (expected one of: ...)".
struct LaneError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The iteration cap of a lane given `:tol=T` without `:N`.
inline constexpr int kToleranceCap = 1000;
// The largest residual tolerance a lane or a solver block takes (`xpbd: {tolerance}`...).
inline constexpr double kMaxResidualTolerance = 0.5;

// One lane, `text` as typed. `integrators_only` (the error reference) refuses the fixed point,
// which is a solver setting of implicit_euler, not a method of the registry.
Lane parse_lane(const std::string& text, bool integrators_only = false);

// A comma-separated list of lanes, or "course" among them (the course framework's four:
// explicit Euler, the fixed-point "implicit", midpoint, RK4). Lanes without @STEP keep dt = 0
// for the door to resolve; the door refuses the same lane twice once the steps are known.
std::vector<Lane> parse_lane_list(const std::string& text);

// Every name a lane may start with, for help and messages: the registry's, the fixed point's.
std::string lane_names_joined(std::string_view separator = ", ");

// The lane's method, step and settings written into a scene, as if the file had said them:
// integrator, dt (when written), the fixed point, and the iterations or tolerance of the
// method's own block.
void apply_lane(SceneDef& scene, const Lane& lane);

// An iteration count as typed (`:N`, --iterations): a whole number from 1 to
// kMaxSolverIterations, else LaneError "`what`: 'x' is not a whole number from 1 to 1000000".
int parse_iteration_count(const std::string& text, const std::string& what);

// "%g" of a step, the way labels and messages write it; one n-th of a second that %g can only
// round is written as the fraction ("1/30").
std::string step_string(double dt);

// "rk4  dt = 1e-4 s": an integrator (`name`) at a step as written (`step`, s), as overlays and
// legends label a lane.
std::string integrator_label(std::string_view name, std::string_view step);

}  // namespace clothsim
