// XPBD (Macklin, Mueller and Chentanez 2016) on the whole scene model:
//     predict y = yhat (inertia, gravity and the air drag, implicitly: step_problem.h), then
//     `iterations` Gauss-Seidel sweeps, each over every spring as a compliant distance
//     constraint (compliance 1/ks, damping beta = kd) and every particle against the
//     ground and kinematic spheres (inequality constraints with friction); v = (y - x_n)/h.
// Converged, it is not implicit_euler's step: the damper's force is the textbook
// kd u u^T (v_a - v_b) at the end of the step, not (kd/h)(l - ln) u, and each projection moves
// along its constraint's gradient at its own iterate, so the end positions carry the sweeps'
// history (docs/integrators.md, "XPBD's gap").
// With a residual tolerance (xpbd.tolerance, a lane's :tol=) a step stops on that residual
// (step_problem.h's ResidualForm::IterateChange).
// Substeps are smaller steps: xpbd@1/600:1 is Macklin et al. 2019's "Small steps".
// On a grid the sweep goes family set by family set in SIMD (solvers/xpbd_family_kernels.h);
// other models sweep the spring list in its order.
#include "integrator.h"

#include <stdexcept>

#include "core/model/barrier_contacts.h"
#include "core/solvers/solver_cache.h"
#include "core/solvers/xpbd_family_kernels.h"
#include "core/solvers/xpbd_kernels.h"

namespace clothsim {
namespace {

void project_springs(const Model& model, const StepProblem& p, const Eigen::VectorXd& inv_mass,
                     Eigen::Matrix3Xd& y, std::vector<double>& lambda) {
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    Vec3 ya = y.col(s.a[k]), yb = y.col(s.b[k]);
    lambda[k] += solve_distance_constraint(ya, yb, p.start.col(s.a[k]), p.start.col(s.b[k]),
                                           inv_mass[s.a[k]], inv_mass[s.b[k]], s.rest[k], s.ks[k],
                                           s.kd[k], p.h, lambda[k]);
    y.col(s.a[k]) = ya;
    y.col(s.b[k]) = yb;
  }
}

void project_contacts(const Model& model, const StepProblem& p, Eigen::Matrix3Xd& y) {
  for (int i = 0; i < model.num_particles; ++i) {
    if (p.weight[i] == 0.0) continue;
    Vec3 yi = y.col(i);
    for_each_penetration(p.colliders, yi, [&](const Penetration& c) {
      solve_contact_constraint(yi, p.start.col(i), p.h, c);
    });
    y.col(i) = yi;
  }
}

// Each returns the sweeps taken (fewer than `iterations` when `stop` was met).
int sweep_spring_list(const Model& model, const StepProblem& p, const State& state, int iterations,
                      SolverCache& cache, const Workspace& ws, ResidualStop& stop) {
  const bool contacts = p.colliders.ground || !p.colliders.centre.empty();
  cache.lambda.assign(model.springs.size(), 0.0);
  for (int it = 0; it < iterations; ++it) {
    project_springs(model, p, state.inv_mass, cache.y, cache.lambda);
    if (contacts) project_contacts(model, p, cache.y);
    if (ws.on_iteration) ws.on_iteration(it + 1, cache.y);
    if (stop.met(cache.y) || ws.interrupted()) return it + 1;
  }
  return iterations;
}

// The observer sees the iterate in y: the sweeps keep it in the families' own arrays.
int sweep_families(const Model& model, const StepProblem& p, const State& state, int iterations,
                   SolverCache& cache, const Workspace& ws, ResidualStop& stop) {
  const bool contacts = p.colliders.ground || !p.colliders.centre.empty();
  xpbd_load_families(model, p, state.inv_mass, cache.y, cache.xpbd);
  int taken = 0;
  while (taken < iterations) {
    const int it = taken++;
    xpbd_family_sweep(model, p.h, cache.xpbd);
    if (contacts) xpbd_family_contacts(model, p, cache.xpbd);
    if (ws.interrupted()) break;
    if (!ws.on_iteration && !stop.active()) continue;
    xpbd_store_families(cache.xpbd, model.num_particles, cache.y);
    if (ws.on_iteration) ws.on_iteration(it + 1, cache.y);
    if (stop.met(cache.y)) break;
  }
  xpbd_store_families(cache.xpbd, model.num_particles, cache.y);
  return taken;
}

}  // namespace

// Refused under collision.model: barrier: XPBD's contacts are inequality constraints projected
// each iteration; a barrier is no constraint to project (its compliance would be the inverse of a
// stiffness that grows without bound), and mixing the two would solve neither model.
StepStats xpbd_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  if (uses_barrier(model)) throw std::invalid_argument("collision.model: " + barrier_refusal(IntegratorKind::Xpbd));
  const double h = ctx.h;
  SolverCache& cache = solver_cache(ws);
  StepProblem& p = cache.problem;
  build_step_problem(model, state, h, p);
  cache.y = p.target;
  const int iterations = iteration_count(ctx.settings, IntegratorKind::Xpbd);
  ResidualStop stop(model, p, ResidualForm::IterateChange, ctx.settings.solvers.xpbd.tolerance, cache.y, cache.gradient);
  StepStats stats;
  stats.newton_iterations = model.spring_path() == SpringPath::Families
                                ? sweep_families(model, p, state, iterations, cache, ws, stop)
                                : sweep_spring_list(model, p, state, iterations, cache, ws, stop);
  stop.report(stats);
  stats.start_strain = max_start_strain(model, p);
  finish_step(p, cache.y, state);
  return stats;
}

}  // namespace clothsim
