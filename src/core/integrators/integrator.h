// One signature for every integrator:
//     StepStats NAME_step(const Model&, State&, double h, Workspace&);
// Each advances the whole state (every particle and sphere body) from t to t + h by its
// textbook method and nothing else: no collisions (resolved once after the step, in
// simulation.cpp), no time or event bookkeeping. integrate() dispatches on the enum.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>

#include "integrator_kind.h"
#include "core/model.h"
#include "core/state.h"

namespace clothsim {

// What one step cost and how its solver fared (the explicit family fills force_evals only).
struct StepStats {
  int force_evals = 0;        // calls of accelerations()/total_forces()
  int newton_iterations = 0;  // implicit_euler (newton); fixed-point iterations for fixed_point
  int cg_iterations = 0;      // summed over the step's linear solves
  int factorizations = 0;     // implicit_euler: sparse Cholesky factors of the step's matrix
  int assemblies = 0;         // implicit_euler: Newton matrices assembled (reuse skips some)
  int factored_cg_iterations = 0;  // of cg_iterations, those preconditioned by the factor
  double residual = 0.0;      // final relative residual of the implicit solve
  bool converged = true;      // false when a solve stalled or hit its cap above tolerance
  double start_strain = 0.0;  // largest (l - l0) / l0 of the state the step started from, read
                              // off the step's first force evaluation (no extra spring pass)
  int contact_constraints = 0;  // implicit_euler: contacts held inside the solve this step
};

struct SolverCache;  // xpbd's, projective_dynamics' and vbd's scratch (solvers/solver_cache.h)
struct SolverCacheDeleter {
  void operator()(SolverCache* cache) const;
};

struct ImplicitCache;  // the implicit solver's sparse pattern and buffers (implicit/implicit_cache.h)
struct ImplicitCacheDeleter {  // defined beside ImplicitCache, so this header need not include it
  void operator()(ImplicitCache* cache) const;
};

// Scratch space owned by one run, so steps allocate nothing. Integrators size what they use.
// Nothing in it carries from one step to the next but sizes and patterns (what does, the
// implicit warm start, lives in State).
struct Workspace {
  Eigen::Matrix3Xd a, x1, v1, a1, x2, v2, a2, a3;  // (3 x B) scratch
  std::unique_ptr<ImplicitCache, ImplicitCacheDeleter> implicit;
  std::unique_ptr<SolverCache, SolverCacheDeleter> solvers;
  // Receives implicit_euler's Newton trace, one line per event (docs/integrators.md, "The
  // Newton trace"); empty: no trace. The tool sets it; the engine reads no environment.
  std::function<void(const char* line)> newton_trace;
  // Told after each iteration of xpbd, projective_dynamics and vbd its number (from 1) and the
  // end-of-step positions it reached (3 x B), before the step ends there; empty: not called.
  // The convergence study (study/convergence.h) records every iteration of one step with it.
  std::function<void(int iteration, const Eigen::Matrix3Xd& y)> on_iteration;
};

StepStats explicit_euler_step(const Model& model, State& state, double h, Workspace& ws);
StepStats symplectic_euler_step(const Model& model, State& state, double h, Workspace& ws);
StepStats midpoint_step(const Model& model, State& state, double h, Workspace& ws);
StepStats rk4_step(const Model& model, State& state, double h, Workspace& ws);
StepStats implicit_euler_step(const Model& model, State& state, double h, Workspace& ws);
StepStats xpbd_step(const Model& model, State& state, double h, Workspace& ws);
StepStats projective_dynamics_step(const Model& model, State& state, double h, Workspace& ws);
StepStats vbd_step(const Model& model, State& state, double h, Workspace& ws);
// How far (m) every particle of an iterate may lie from the Newton matrix's linearisation
// point for implicit_euler to reuse that matrix whatever the residual (implicit_euler.cpp,
// kReuseChange): 0.05 l_min / (4 (h c_max + (h w_max)^2)); infinite without springs.
double implicit_reuse_reach(const Model& model, double h);

StepStats integrate(IntegratorKind kind, const Model& model, State& state, double h, Workspace& ws);

// Force evaluations per step of the explicit family (1, 1, 2, 4); 0 for implicit_euler and
// the iterative solvers, whose cost depends on their iterations.
int nominal_force_evals(IntegratorKind kind);

}  // namespace clothsim
