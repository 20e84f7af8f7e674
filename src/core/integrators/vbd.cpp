// Vertex block descent (Chen et al. 2024) on the whole scene model: from the paper's adaptive
// first guess, `iterations` Gauss-Seidel sweeps over a colouring of the springs' graph, each
// vertex taking one 3x3 Newton step on the step's G with the others held (solvers/
// vbd_kernels.h); v = (y - x_n)/h. G is implicit_euler's Phi (the seed's dampers as
// (kd/h)(l - ln)), so converged VBD is backward Euler; contacts are the paper's quadratic
// penalty along the collider's normal, not implicit_euler's held planes.
#include "integrator.h"
#include "core/forces.h"
#include "core/solvers/solver_cache.h"

namespace clothsim {

StepStats vbd_step(const Model& model, State& state, double h, Workspace& ws) {
  SolverCache& c = solver_cache(ws);
  build_step_problem(model, state, h, c.problem);
  build_vbd_graph(model, c.vbd);
  StepStats stats;
  stats.start_strain = accelerations(model, state.x, state.v, state.inv_mass, c.acceleration);
  stats.force_evals = 1;
  vbd_initial_guess(model, c.problem, state, c.acceleration, c.y);
  const int iterations = iteration_count(model, IntegratorKind::Vbd);
  for (int it = 0; it < iterations; ++it) {
    vbd_sweep(model, c.problem, c.vbd, c.y);
    if (ws.on_iteration) ws.on_iteration(it + 1, c.y);
  }
  stats.newton_iterations = iterations;
  finish_step(c.problem, c.y, state);
  return stats;
}

}  // namespace clothsim
