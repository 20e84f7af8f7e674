#include "convergence.h"

#include <algorithm>
#include <cmath>

#include "core/simulation.h"
#include "core/solvers/step_problem.h"

namespace clothsim {
namespace {

// The reference's solve: converged hard (the point is the distance from the solution).
Model reference_model(const Model& model) {
  Model m = model;
  m.implicit.solver = ImplicitSolver::Newton;
  m.implicit.newton_tolerance = std::min(m.implicit.newton_tolerance, 1e-10);
  m.implicit.newton_max_iterations = std::max(m.implicit.newton_max_iterations, 200);
  return m;
}

void set_iterations(Model& m, IntegratorKind kind, int n) {
  if (kind == IntegratorKind::ImplicitEuler) m.implicit.newton_max_iterations = n;
  if (kind == IntegratorKind::Xpbd) m.solvers.xpbd.iterations = n;
  if (kind == IntegratorKind::ProjectiveDynamics) m.solvers.projective_dynamics.iterations = n;
  if (kind == IntegratorKind::Vbd) m.solvers.vbd.iterations = n;
}

// K states along the converged run, evenly in steps over the scene's duration.
std::vector<State> sample_states(const Model& reference, double h, int k) {
  const long steps = std::max<long>(1, std::lround(reference.duration / h));
  std::vector<State> states;
  State s = initial_state(reference);
  Workspace ws;
  for (int i = 0; i < k; ++i) {
    const long at = std::max<long>(1, steps * i / k);
    while (s.step < at) step(reference, s, IntegratorKind::ImplicitEuler, h, ws);
    states.push_back(s);
  }
  return states;
}

void measure(const Model& model, const State& end, const State& reference, ConvergencePoint& p,
             double h, const State& start) {
  const int P = model.num_particles;
  const Eigen::VectorXd d = (end.x.leftCols(P) - reference.x.leftCols(P)).colwise().norm();
  p.rms = std::sqrt(d.squaredNorm() / P);
  p.max = d.maxCoeff();
  StepProblem problem;
  build_step_problem(model, start, h, problem);
  Eigen::Matrix3Xd gradient;
  p.gradient = step_gradient(model, problem, end.x, gradient);
}

}  // namespace

std::vector<ConvergencePoint> convergence_study(const Model& model, const ConvergenceSpec& spec,
                                                const std::function<void(int, int)>& progress) {
  const Model reference = reference_model(model);
  const std::vector<State> states = sample_states(reference, spec.h, spec.states);
  std::vector<ConvergencePoint> points;
  const int total = static_cast<int>(states.size() * spec.methods.size());
  int done = 0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    State be = states[k];
    Workspace ref_ws;
    step(reference, be, IntegratorKind::ImplicitEuler, spec.h, ref_ws);
    for (IntegratorKind method : spec.methods) {
      Model m = model;  // one model and workspace per sweep: a factor or colouring is reused,
      Workspace ws;     // as in a run, and the CPU is the iterations'
      State warm = states[k];
      step(m, warm, method, spec.h, ws);  // warm the caches
      for (int n = 1; n <= spec.max_iterations; ++n) {
        set_iterations(m, method, n);
        State s = states[k];
        const double cpu = thread_cpu_seconds();
        step(m, s, method, spec.h, ws);
        ConvergencePoint p{method, static_cast<int>(k), states[k].t, n};
        p.cpu_seconds = thread_cpu_seconds() - cpu;
        measure(model, s, be, p, spec.h, states[k]);
        points.push_back(p);
      }
      if (progress) progress(++done, total);
    }
  }
  return points;
}

}  // namespace clothsim
