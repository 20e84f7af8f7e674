// One signature for every integrator:
//     StepStats NAME_step(const Model&, State&, const StepContext&, Workspace&);
// Each advances the whole state (every particle and sphere body) from t to t + h by its
// textbook method and nothing else: no collisions (resolved once after the step, in
// simulation.cpp), no time or event bookkeeping. integrate() dispatches on the enum.
#pragma once

#include "integrator_kind.h"
#include "core/base/step_context.h"
#include "core/base/step_stats.h"
#include "core/base/workspace.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

StepStats explicit_euler_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats symplectic_euler_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats midpoint_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats rk4_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats implicit_euler_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats xpbd_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats projective_dynamics_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats vbd_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats velocity_verlet_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats yoshida4_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats implicit_midpoint_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats newmark_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats generalized_alpha_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats bdf2_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats ros2_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats imex_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
// imex's step matrix on (u, u', a) for u'' + c u' + w^2 u = 0 (analysis::StepMatrix), a the
// carried a(x_n, v_n), and its largest stable step, Jury's condition on that matrix (imex.cpp):
// 2 / w undamped and growing with c, past analysis::step_matrix_limit's scan (4 / |root|).
void imex_matrix(double h, double w, double c, double m[9]);
double imex_limit(double w, double c);
// How far (m) every particle of an iterate may lie from the Newton matrix's linearisation
// point for implicit_euler to reuse that matrix whatever the residual (implicit_euler.cpp,
// kReuseChange): 0.05 l_min / (4 (h c_max + (h w_max)^2)); infinite without springs.
double implicit_reuse_reach(const Model& model, double h);

// One step of `kind` under `settings` (a run's: method_settings.h). The form without them
// steps under the model's own (Model::method_defaults()), as a test or a benchmark does.
StepStats integrate(IntegratorKind kind, const Model& model, const MethodSettings& settings, State& state,
                    double h, Workspace& ws);
StepStats integrate(IntegratorKind kind, const Model& model, State& state, double h, Workspace& ws);

// Force evaluations per step of the explicit family (1, 1, 2, 4); 0 for implicit_euler and
// the iterative solvers, whose cost depends on their iterations.
int nominal_force_evals(IntegratorKind kind);

}  // namespace clothsim
