// Vertex block descent (Chen et al. 2024) on the whole scene model: from the paper's adaptive
// first guess, `iterations` Gauss-Seidel sweeps over a colouring of the springs' graph, each
// vertex taking one 3x3 Newton step on the step's G with the others held (solvers/
// vbd_kernels.h); v = (y - x_n)/h. G is implicit_euler's Phi (the seed's dampers as
// (kd/h)(l - ln)), so converged VBD is backward Euler; contacts are hard constraints on
// implicit_euler's held planes (solvers/vbd_kernels.h's vbd_hold), not the paper's penalty.
// With vbd.chebyshev_rho > 0, the paper's accelerated iterations (Wang 2015's Chebyshev
// weights) over the free vertices off the colliders. With vbd.tolerance > 0 a step stops on its
// residual (solver_cache.h's ResidualStop). The held vertices, just beyond the reach the
// post-step response acts within, get implicit_euler's held response there (friction included).
// Under collision.model: barrier, the paper's own contact: the barrier in each vertex's Newton
// step with a step filter (vbd_kernels.h); the residual stop then stays off (its residual is
// Phi's gradient without the barrier), so a lane runs its :N sweeps.
#include "integrator.h"
#include "core/model/barrier_contacts.h"
#include "core/model/forces.h"
#include "core/solvers/solver_cache.h"
#include "core/solvers/vbd_grid_kernels.h"

namespace clothsim {
namespace {

// The paper's accelerated iterations on the spring graph's iterate (as vbd_grid_accelerate).
void accelerate_graph(const Model& model, SolverCache& c, int k, double omega) {
  if (k >= 2)
    for (int i = 0; i < model.num_particles; ++i) {
      const VbdContact& contact = c.vbd_contacts[static_cast<std::size_t>(i)];
      if (c.problem.weight[i] > 0.0 && !contact.planed && !contact.held)
        c.y.col(i) = omega * (c.y.col(i) - c.y_before.col(i)) + c.y_before.col(i);
    }
  std::swap(c.y_before, c.y_next);
}

// The particles held on their planes at c.y (c.held): those that took a plane this step and lie on it.
void vbd_collect_held(const Model& model, SolverCache& c) {
  c.held.clear();
  const bool grid = vbd_by_grid(model);
  for (int i = 0; i < model.num_particles; ++i) {
    const VbdContact& contact = grid ? c.vbd_grid.contact[static_cast<std::size_t>(c.vbd_grid.index[i])]
                                     : c.vbd_contacts[static_cast<std::size_t>(i)];
    if (contact.planed && c.problem.weight[i] > 0.0) add_if_on_plane(i, contact.normal, contact.plane, c.y.col(i), c.held);
  }
}

bool stop_met(const Model& model, SolverCache& c, ResidualStop& stop) {
  if (!stop.active()) return false;
  vbd_collect_held(model, c);
  return stop.met(c.y, &c.held);
}

// On a grid: the particles' sweeps in SIMD over the grid's nine colours, then the other
// bodies' (dynamic spheres: no springs, so no coupling within the step).
// The observer sees the particles' iterate in y (the sweeps keep it in the grid's arrays).
// Returns the sweeps taken (fewer than `iterations` when `stop` was met); rho: vbd's chebyshev_rho.
int sweep_grid(const Model& model, int iterations, double rho, SolverCache& c, const Workspace& ws,
               ResidualStop& stop) {
  double omega = 1.0;
  vbd_load_grid(model, c.problem, c.y, c.vbd_grid);
  int taken = 0;
  while (taken < iterations) {
    const int it = taken++;
    if (rho > 0.0) vbd_grid_remember(c.vbd_grid, it + 1);
    vbd_grid_sweep(model, c.problem, c.vbd_grid);
    if (rho > 0.0) vbd_grid_accelerate(c.vbd_grid, it + 1, omega = chebyshev_omega(it + 1, rho, omega));
    if (ws.interrupted()) break;
    if (!ws.on_iteration && !stop.active()) continue;
    vbd_store_grid(model, c.vbd_grid, c.y);
    if (ws.on_iteration) ws.on_iteration(it + 1, c.y);
    if (stop_met(model, c, stop)) break;
  }
  vbd_store_grid(model, c.vbd_grid, c.y);
  const Eigen::VectorXd& a = c.problem.weight;
  if ((a.tail(model.num_bodies() - model.num_particles).array() > 0.0).any())  // a dynamic sphere
    for (int it = 0; it < taken; ++it) vbd_sweep(c.problem, c.vbd, c.y, c.vbd_contacts, model.num_particles);
  return taken;
}

// Elsewhere, and under the barrier: the greedy colouring's scalar sweeps over every body.
// The barrier's sweeps are not accelerated: a Chebyshev extrapolation of a vertex could carry
// it through a collider, past the step filter.
int sweep_graph(const Model& model, int iterations, double chebyshev_rho, SolverCache& c, const Workspace& ws,
                ResidualStop& stop, const VbdBarrier* barrier) {
  const double rho = barrier ? 0.0 : chebyshev_rho;
  double omega = 1.0;
  if (rho > 0.0) c.y_before = c.y;
  for (int it = 0; it < iterations; ++it) {
    if (rho > 0.0) c.y_next = c.y;
    vbd_sweep(c.problem, c.vbd, c.y, c.vbd_contacts, 0, barrier);
    if (rho > 0.0) accelerate_graph(model, c, it + 1, omega = chebyshev_omega(it + 1, rho, omega));
    if (ws.on_iteration) ws.on_iteration(it + 1, c.y);
    if (stop_met(model, c, stop) || ws.interrupted()) return it + 1;
  }
  return iterations;
}

}  // namespace

StepStats vbd_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  const double h = ctx.h;
  SolverCache& c = solver_cache(ws);
  build_step_problem(model, state, h, c.problem);
  build_vbd_graph(model, c.vbd);
  StepStats stats;
  stats.start_strain = accelerations(model, state.x, state.v, state.inv_mass, c.acceleration);
  stats.force_evals = 1;
  vbd_initial_guess(model, c.problem, state, c.acceleration, c.y);
  c.vbd_contacts.assign(model.num_particles, VbdContact{});
  const VbdDef& cfg = ctx.settings.solvers.vbd;
  const int iterations = iteration_count(ctx.settings, IntegratorKind::Vbd);
  const bool barrier_scene = uses_barrier(model);
  ResidualStop stop(model, c.problem, ResidualForm::StepPotential, barrier_scene ? 0.0 : cfg.tolerance, c.y,
                    c.gradient);
  if (barrier_scene) {
    push_out_of_colliders(model, state.inv_mass, c.y);  // a guess inside a collider: G is infinite there
    const VbdBarrier barrier{&model, &state.x, &state.inv_mass, h};
    stats.newton_iterations = sweep_graph(model, iterations, cfg.chebyshev_rho, c, ws, stop, &barrier);
  } else if (vbd_by_grid(model)) {
    stats.newton_iterations = sweep_grid(model, iterations, cfg.chebyshev_rho, c, ws, stop);
  } else {
    stats.newton_iterations = sweep_graph(model, iterations, cfg.chebyshev_rho, c, ws, stop, nullptr);
  }
  stop.report(stats);
  finish_step(c.problem, c.y, state);
  if (barrier_scene) return stats;  // no held planes: the barrier and its friction acted in the sweeps
  vbd_collect_held(model, c);
  respond_to_held_contacts(model, c.problem, c.y, c.held, c.gradient, state);  // friction on them
  return stats;
}

}  // namespace clothsim
