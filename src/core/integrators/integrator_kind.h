// The integrators by name and their registry rows. The enum (core/method_params.h) is what a
// scene's `integrator:` key and the CLI's --integrator parse into; the step dispatches on it
// in integrator.cpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/integrators/method_memory.h"
#include "core/base/method_params.h"
#include "core/model/model.h"
#include "core/model/stiffness_estimate.h"

namespace clothsim {

// What a lane's `:N`, --iterations and convergence sweeps set for a method.
enum class IterationControl {
  None,    // the explicit family: a step is a fixed number of force evaluations
  Newton,  // implicit_euler's Newton iterations (1: Baraff & Witkin's step, NewtonMode)
  Solver,  // an iterative solver's sweeps per step (xpbd, projective_dynamics, vbd)
};

// Everything said about an integrator outside its step function, in one table (the
// registry, integrators/integrator.cpp): names, help, default lists, cost, stability and
// iteration control all read their method's row, so a new method is its step function, its
// folder and one row.
struct IntegratorInfo {
  IntegratorKind kind;
  std::string_view name;         // scene/CLI spelling
  int nominal_force_evals;       // per step; 0 where the solve decides (implicit_euler)
  int comparison_slot;           // place in compare's, bench's and stability's default four
                                 // (1..4, the course's order), 0: not among them
  std::string_view description;  // one line, for --help
  int order;                     // global order on a smooth ODE (what bench's slopes should read)
  IterationControl iterations;   // what `:N` sets
  // Spring-pass equivalents of one solver iteration (work_units.h; BENCHMARKS.md, "The
  // iterative solvers"); 0 unless iterations is Solver.
  double passes_per_iteration;
  // Also measured at one step per video frame by bench and stability (a method run at frame
  // rate, which no explicit step survives on a stiff scene).
  bool frame_rate_steps;
  // Its post-step projection is a safety net, counted when it moves a particle (contacts are
  // held inside the solve): RunTotals::safety_projections.
  bool counts_safety_projections;
  // The largest stable h on u'' + c u' + w^2 u = 0 (stiffness_estimate.h); inf: none.
  double (*linear_limit)(double w, double c, const ImplicitDef& implicit);
  // Why the method cannot run collision.model: barrier (docs/integrators.md), or empty.
  std::string_view barrier_refusal;
  // Bytes of one run beyond the Model, and of the final state it keeps (method_memory.h).
  MethodMemory (*memory)(const MemorySizes& sizes);
  // Its order where forces depend on velocity (dampers, drag, friction), when lower than
  // `order`: yoshida4's composition needs a symmetric Verlet kick (verlet.h). 0: `order`.
  int velocity_force_order = 0;
  // An adaptive pair (integrators/adaptive.h): Run steps it under error control, by its
  // tolerances (MethodSettings::adaptive), from the lane's step as the first trial.
  bool adaptive = false;
  // The method's own parameters a lane sets as :KEY=VALUE (method_param.h), comma-separated:
  // "beta,gamma" for newmark, "rho" for generalized_alpha; empty for none.
  std::string_view parameters = "";
};
const std::vector<IntegratorInfo>& integrator_registry();  // in enum order

std::string_view integrator_name(IntegratorKind kind);

// The course's "implicit" (implicit_euler with `implicit: {solver: fixed_point}`) is another
// method, amplification 1 + z + z^2 rather than 1 / (1 - z), so everything that names a run
// (metrics, summaries, tables, overlays) calls it by this name, never implicit_euler.
inline constexpr std::string_view kFixedPointName = "implicit_euler_fixed_point";
// What a run of `kind` under `implicit` is called: kFixedPointName, or the integrator's name.
std::string method_name(IntegratorKind kind, const ImplicitDef& implicit);
std::optional<IntegratorKind> parse_integrator(std::string_view name);
const std::vector<IntegratorKind>& all_integrators();
std::string integrator_names_joined(std::string_view separator = ", ");  // for errors and help
std::string default_comparison_list();  // the default four, comma-separated
std::vector<IntegratorKind> comparison_integrators();  // the same four, in their slots' order

const IntegratorInfo& integrator_info(IntegratorKind kind);  // the method's row
// "NAME has no barrier contact ...", or "" when `kind` takes collision.model: barrier.
std::string barrier_refusal(IntegratorKind kind);
// Whether `:N` sets a solver's sweeps (xpbd, projective_dynamics, vbd).
inline bool is_iterative_solver(IntegratorKind kind) {
  return integrator_info(kind).iterations == IterationControl::Solver;
}
// The iteration count `:N` sets for `kind` in a run's settings (its Newton cap, or its solver
// block's sweeps); null for the explicit family.
int* iteration_count(MethodSettings& settings, IntegratorKind kind);
int iteration_count(const MethodSettings& settings, IntegratorKind kind);  // 0 for the explicit family
// The same in a scene's settings (a lane written into its scene: scene/lane.h), and in a
// model's defaults (what a run of the model starts from).
int* iteration_count(ImplicitDef& implicit, SolverDefs& solvers, IntegratorKind kind);
int* iteration_count(Model& model, IntegratorKind kind);
int iteration_count(const Model& model, IntegratorKind kind);
// The residual tolerance `:tol=` sets for `kind` (an iterative solver's; solvers/solver_cache.h's
// ResidualStop), or null for a method without one.
double* residual_tolerance(MethodSettings& settings, IntegratorKind kind);
double* residual_tolerance(ImplicitDef& implicit, SolverDefs& solvers, IntegratorKind kind);
double* residual_tolerance(Model& model, IntegratorKind kind);

// Two methods have roles beyond their rows. Backward Euler is what the iterative solvers are
// measured against (clothsim converge) and has the course's fixed-point spelling; RK4 is the
// fine fixed-step reference of bench and compare, dopri5 the adaptive one.
inline constexpr IntegratorKind kBackwardEuler = IntegratorKind::ImplicitEuler;
inline constexpr IntegratorKind kReferenceIntegrator = IntegratorKind::Rk4;
// The adaptive reference's pair on a smooth scene (study/reference.h: Boost.Odeint's dopri5).
inline constexpr IntegratorKind kAdaptiveReferenceIntegrator = IntegratorKind::Dopri5;

namespace analysis {
// The step beyond which `kind` is predicted to be unstable on the scene's fastest mode
// (stiffness_estimate.h says how): the row's linear_limit at w_max and c_max; infinity with
// nothing stiff in the scene.
double predicted_limit(const StiffnessEstimate& estimate, IntegratorKind kind, const ImplicitDef& implicit = {});
}  // namespace analysis

}  // namespace clothsim
