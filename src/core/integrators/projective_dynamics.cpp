// Projective dynamics (Liu, Bargteil, O'Brien and Kavan 2013) on the whole scene model: from
// the inertial target, `iterations` local-global iterations on the step's G
// (solvers/pd_kernels.h), each a pass over the springs (local projections) and one solve with
// the prefactored matrix M/h^2 + L (+ the contact weights); v = (y - x_n)/h. Each spring and
// its damper are one spring of stiffness ks + kd/h about a blended rest length, so G is
// exactly implicit_euler's Phi and converged PD is backward Euler. Contacts are multipliers
// in the right-hand side raised by each solve's penetration (Uzawa; solvers/pd_kernels.h says
// why not Bouaziz et al.'s weighted terms). With projective_dynamics.chebyshev_rho > 0, Wang 2015's
// Chebyshev semi-iterative acceleration from the third iteration on. With
// projective_dynamics.tolerance > 0 a step stops on its residual (solver_cache.h's ResidualStop).
// The held particles, just beyond the reach the post-step response acts within, get
// implicit_euler's held response there (friction included).
#include "integrator.h"

#include <algorithm>
#include <stdexcept>

#include "core/model/barrier_contacts.h"
#include "core/solvers/solver_cache.h"

namespace clothsim {
namespace {

// Wang 2015: y_{k+1} = omega_{k+1} (local-global(y_k) - y_{k-1}) + y_{k-1}, with c.y holding
// local-global(y_k) and c.y_before y_{k-1}.
void accelerate(SolverCache& c, int k, double rho, double& omega) {
  omega = chebyshev_omega(k, rho, omega);
  if (k >= 2) c.y = omega * (c.y - c.y_before) + c.y_before;
}

// The particles held on their planes at c.y (c.held): those whose contact multiplier pushes,
// with it as their contact force.
void pd_collect_held(const Model& model, SolverCache& c) {
  c.held.clear();
  for (int i = 0; i < model.num_particles; ++i)
    if (c.pd_system.planed[i] && c.problem.weight[i] > 0.0 && c.lambda[i] > 0.0)
      c.held.push_back(HeldContact{i, c.pd_system.normal[i], c.lambda[i]});
}

}  // namespace

// Refused under collision.model: barrier: PD's global matrix is prefactored once, which needs
// every energy quadratic in a projection; the barrier's curvature grows without bound as a
// distance closes, so it has no fixed weight to prefactor (Lan et al. 2022 need a different
// solver for it).
StepStats projective_dynamics_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  if (uses_barrier(model)) throw std::invalid_argument("collision.model: " + barrier_refusal(IntegratorKind::ProjectiveDynamics));
  const double h = ctx.h;
  SolverCache& c = solver_cache(ws);
  build_step_problem(model, state, h, c.problem);
  StepStats stats;
  stats.factorizations = pd_prepare_factor(model, c.problem, state.inv_mass, c.pd) ? 1 : 0;
  const double rho = ctx.settings.solvers.projective_dynamics.chebyshev_rho;
  const int iterations = iteration_count(ctx.settings, IntegratorKind::ProjectiveDynamics);
  pd_prepare_step(model, c.problem, c.pd, c.pd_system);
  c.y = c.problem.target;
  c.lambda.assign(model.num_particles, 0.0);
  double omega = 1.0;
  c.y_before = c.y;
  const double tolerance = ctx.settings.solvers.projective_dynamics.tolerance;
  ResidualStop stop(model, c.problem, ResidualForm::StepPotential, tolerance, c.y, c.gradient);
  int k = 1;
  for (; k <= iterations; ++k) {
    c.y_next = c.y;  // y_k
    pd_iteration(model, c.problem, c.pd, c.y, c.pd_system, c.lambda);
    if (rho > 0.0) accelerate(c, k, rho, omega);
    c.y_before = c.y_next;
    if (ws.on_iteration) ws.on_iteration(k, c.y);
    if (ws.interrupted()) break;
    if (!stop.active()) continue;
    pd_collect_held(model, c);
    if (stop.met(c.y, &c.held)) break;
  }
  stats.newton_iterations = std::min(k, iterations);
  stop.report(stats);
  stats.start_strain = max_start_strain(model, c.problem);
  finish_step(c.problem, c.y, state);
  pd_collect_held(model, c);
  respond_to_held_contacts(model, c.problem, c.y, c.held, c.gradient, state);  // friction on them
  return stats;
}

}  // namespace clothsim
