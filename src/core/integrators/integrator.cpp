// The registry and the dispatch: one table, one lookup, one function per method (MuJoCo's
// mj_step pattern). Adding an integrator is one row here, its step function and its folder.
#include "integrator.h"

#include "adaptive.h"
#include "verlet.h"

#include <iterator>
#include <limits>
#include <stdexcept>

namespace clothsim {
namespace {

using StepFunction = StepStats (*)(const Model&, State&, const StepContext&, Workspace&);

struct Entry {
  IntegratorInfo info;
  StepFunction step;
  int* (*iterations)(ImplicitDef& implicit, SolverDefs& solvers);  // the count `:N` sets, or null
  double* (*tolerance)(ImplicitDef& implicit, SolverDefs& solvers);  // the residual tolerance `:tol=` sets, or null
};

constexpr double kInf = std::numeric_limits<double>::infinity();
double no_limit(double, double, const ImplicitDef&) { return kInf; }
double explicit_euler_limit(double w, double c, const ImplicitDef&) { return analysis::explicit_limit(1, w, c); }
double midpoint_limit(double w, double c, const ImplicitDef&) { return analysis::explicit_limit(2, w, c); }
double rk4_limit(double w, double c, const ImplicitDef&) { return analysis::explicit_limit(4, w, c); }
double symplectic_limit(double w, double c, const ImplicitDef&) { return analysis::symplectic_euler_limit(w, c); }
double verlet_limit(double w, double c, const ImplicitDef&) {
  return analysis::step_matrix_limit(velocity_verlet_matrix, w, c);
}
double yoshida4_limit(double w, double c, const ImplicitDef&) {
  return analysis::step_matrix_limit(yoshida4_matrix, w, c);
}
// imex on one mode is stable for w h < 2 and beyond with c (imex_limit), but w_max and c_max
// bound different modes (a damper acts along its spring only; bending and the barrier go
// undamped), so the prediction is the undamped mode's 2 / w_max: the single mode's 0.075 s on
// drape.yaml overstated a limit between 1e-3 and 1.5e-3 s (docs/integrators.md).
double imex_row_limit(double w, double, const ImplicitDef&) { return imex_limit(w, 0.0); }
double backward_euler_limit(double w, double c, const ImplicitDef& implicit) {
  if (implicit.solver == ImplicitSolver::Newton) return kInf;  // A-stable
  return analysis::fixed_point_limit(implicit.fixed_point_iterations, w, c);
}

int* no_iterations(ImplicitDef&, SolverDefs&) { return nullptr; }
int* newton_iterations(ImplicitDef& i, SolverDefs&) { return &i.newton_max_iterations; }
int* xpbd_iterations(ImplicitDef&, SolverDefs& s) { return &s.xpbd.iterations; }
int* pd_iterations(ImplicitDef&, SolverDefs& s) { return &s.projective_dynamics.iterations; }
int* vbd_iterations(ImplicitDef&, SolverDefs& s) { return &s.vbd.iterations; }
double* no_tolerance(ImplicitDef&, SolverDefs&) { return nullptr; }
double* xpbd_tolerance(ImplicitDef&, SolverDefs& s) { return &s.xpbd.tolerance; }
double* pd_tolerance(ImplicitDef&, SolverDefs& s) { return &s.projective_dynamics.tolerance; }
double* vbd_tolerance(ImplicitDef&, SolverDefs& s) { return &s.vbd.tolerance; }

// In enum order, so an entry is found by the enum's value. The solvers' passes per iteration
// are the work-unit weights measured on the drape's 25 x 25 sheet (BENCHMARKS.md).
using C = IterationControl;
// XPBD and PD project constraints; the barrier is a potential they have no faithful form of.
constexpr std::string_view kProjectsConstraints =
    "has no barrier contact (it projects constraints); use collision.model: projection for it";
// ros2's step is linearly implicit: no line search keeps the barrier's distances positive.
constexpr std::string_view kLinearlyImplicit =
    "has no barrier contact (a linearly implicit step has no line search to keep its distances "
    "positive); use collision.model: projection for it";
constexpr Entry kRegistry[] = {  // constant-initialized: safe to read during static initialization
    {{IntegratorKind::ExplicitEuler, "explicit_euler", 1, 1,
      "forward Euler: x += h v_n, v += h a_n (the course framework's 'explicit')",
      1, C::None, 0.0, false, false, explicit_euler_limit, "", explicit_family_memory},
     explicit_euler_step, no_iterations, no_tolerance},
    {{IntegratorKind::SymplecticEuler, "symplectic_euler", 1, 0,
      "v += h a_n, x += h v_{n+1} (the student report's code)",
      1, C::None, 0.0, false, false, symplectic_limit, "", explicit_family_memory},
     symplectic_euler_step, no_iterations, no_tolerance},
    {{IntegratorKind::Midpoint, "midpoint", 2, 3, "RK2 through the half-step state",
      2, C::None, 0.0, false, false, midpoint_limit, "", midpoint_memory},
     midpoint_step, no_iterations, no_tolerance},
    {{IntegratorKind::Rk4, "rk4", 4, 4, "classic Runge-Kutta 4 on (x, v)",
      4, C::None, 0.0, false, false, rk4_limit, "", rk4_memory},
     rk4_step, no_iterations, no_tolerance},
    {{IntegratorKind::ImplicitEuler, "implicit_euler", 0, 2,
      "backward Euler: Newton + PCG, contacts in the solve (or fixed point)",
      1, C::Newton, 0.0, true, true, backward_euler_limit, "", implicit_euler_memory},
     implicit_euler_step, newton_iterations, no_tolerance},
    {{IntegratorKind::Xpbd, "xpbd", 0, 0,
      "XPBD (Macklin et al. 2016): compliant distance constraints, Gauss-Seidel",
      1, C::Solver, 1.4, false, false, no_limit, kProjectsConstraints, xpbd_memory},
     xpbd_step, xpbd_iterations, xpbd_tolerance},
    {{IntegratorKind::ProjectiveDynamics, "projective_dynamics", 0, 0,
      "projective dynamics (Liu et al. 2013): local-global on Phi, prefactored",
      1, C::Solver, 2.9, false, false, no_limit, kProjectsConstraints,
      projective_dynamics_memory},
     projective_dynamics_step, pd_iterations, pd_tolerance},
    {{IntegratorKind::Vbd, "vbd", 0, 0,
      "vertex block descent (Chen et al. 2024): per-vertex Newton on Phi",
      1, C::Solver, 2.4, false, false, no_limit, "", vbd_memory},
     vbd_step, vbd_iterations, vbd_tolerance},
    {{IntegratorKind::VelocityVerlet, "velocity_verlet", 1, 0,
      "Stormer-Verlet kick-drift-kick: symplectic, order 2, one force pass a step",
      2, C::None, 0.0, false, false, verlet_limit, "", verlet_memory},
     velocity_verlet_step, no_iterations, no_tolerance},
    {{IntegratorKind::Yoshida4, "yoshida4", 3, 0,
      "Yoshida's symplectic 4th-order composition of three Verlet steps",
      4, C::None, 0.0, false, false, yoshida4_limit, "", verlet_memory, 2},
     yoshida4_step, no_iterations, no_tolerance},
    // The implicit family (implicit_family.h): A-stable (newmark with 2 beta >= gamma >= 1/2,
    // its default among them), so no step limit; `:N` caps Newton as for implicit_euler.
    {{IntegratorKind::ImplicitMidpoint, "implicit_midpoint", 0, 0,
      "implicit midpoint: symplectic, order 2, |R| = 1; a backward Euler half step, then the forward half",
      2, C::Newton, 0.0, true, true, no_limit, "", implicit_family_memory},
     implicit_midpoint_step, newton_iterations, no_tolerance},
    {{IntegratorKind::Newmark, "newmark", 0, 0,
      "Newmark (beta, gamma), the trapezoidal rule by default: order 2, |R| = 1",
      2, C::Newton, 0.0, true, true, no_limit, "", implicit_family_memory, 0, false, "beta,gamma"},
     newmark_step, newton_iterations, no_tolerance},
    {{IntegratorKind::GeneralizedAlpha, "generalized_alpha", 0, 0,
      "generalized-alpha (Chung & Hulbert 1993): order 2, high modes damped to rho_inf",
      2, C::Newton, 0.0, true, true, no_limit, "", implicit_family_memory, 0, false, "rho"},
     generalized_alpha_step, newton_iterations, no_tolerance},
    {{IntegratorKind::Bdf2, "bdf2", 0, 0,
      "BDF2: order 2, L-stable, started (and restarted) by a backward Euler step",
      2, C::Newton, 0.0, true, true, no_limit, "", implicit_family_memory},
     bdf2_step, newton_iterations, no_tolerance},
    {{IntegratorKind::Ros2, "ros2", 2, 0,
      "ROS2 (Verwer et al. 1999): two-stage L-stable Rosenbrock, order 2, one matrix a step",
      2, C::None, 0.0, true, false, no_limit, kLinearlyImplicit, implicit_euler_memory},
     ros2_step, no_iterations, no_tolerance},
    // The adaptive pairs: the step is their controller's, so no step limit is stated; as
    // fixed-step methods, their higher-order solutions (adaptive.h).
    {{IntegratorKind::Bs3, "bs3", 0, 0, "Bogacki-Shampine 3(2) by tolerance: adaptive, order 3",
      3, C::None, 0.0, false, false, no_limit, "", bs3_memory, 0, true},
     bs3_step, no_iterations, no_tolerance},
    {{IntegratorKind::Dopri5, "dopri5", 0, 0, "Dormand-Prince 5(4) by tolerance: adaptive, order 5",
      5, C::None, 0.0, false, false, no_limit, "", dopri5_memory, 0, true},
     dopri5_step, no_iterations, no_tolerance},
    {{IntegratorKind::Rkf78, "rkf78", 0, 0, "Fehlberg 7(8) by tolerance: adaptive, order 8",
      8, C::None, 0.0, false, false, no_limit, "", rkf78_memory, 0, true},
     rkf78_step, no_iterations, no_tolerance},
    // Explicit in the springs, so the stiffness bounds its step (2 / w undamped), never the damper.
    {{IntegratorKind::Imex, "imex", 1, 0,
      "IMEX (Bridson et al. 2003): springs explicit, damping implicit; order 1 (2 undamped)",
      1, C::None, 0.0, false, false, imex_row_limit, "", imex_memory},
     imex_step, no_iterations, no_tolerance},
};

const Entry& entry(IntegratorKind kind) {
  const auto index = static_cast<std::size_t>(kind);
  if (index >= std::size(kRegistry) || kRegistry[index].info.kind != kind)
    throw std::logic_error("integrator registry: no entry for this kind");
  return kRegistry[index];
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_registry() {
  static const std::vector<IntegratorInfo> infos = [] {
    std::vector<IntegratorInfo> out;
    for (const Entry& e : kRegistry) out.push_back(e.info);
    return out;
  }();
  return infos;
}

StepStats integrate(IntegratorKind kind, const Model& model, const MethodSettings& settings, State& state,
                    double h, Workspace& ws) {
  return entry(kind).step(model, state, make_step_context(h, model.spring_path(), settings), ws);
}

StepStats integrate(IntegratorKind kind, const Model& model, State& state, double h, Workspace& ws) {
  return integrate(kind, model, model.method_defaults(), state, h, ws);
}

int nominal_force_evals(IntegratorKind kind) { return entry(kind).info.nominal_force_evals; }

const IntegratorInfo& integrator_info(IntegratorKind kind) { return entry(kind).info; }

std::string barrier_refusal(IntegratorKind kind) {
  const IntegratorInfo& info = entry(kind).info;
  return info.barrier_refusal.empty() ? "" : std::string(info.name) + " " + std::string(info.barrier_refusal);
}

int* iteration_count(ImplicitDef& implicit, SolverDefs& solvers, IntegratorKind kind) {
  return entry(kind).iterations(implicit, solvers);
}

int* iteration_count(MethodSettings& s, IntegratorKind kind) { return iteration_count(s.implicit, s.solvers, kind); }

int iteration_count(const MethodSettings& settings, IntegratorKind kind) {
  MethodSettings& s = const_cast<MethodSettings&>(settings);  // only read
  const int* n = entry(kind).iterations(s.implicit, s.solvers);
  return n ? *n : 0;
}

int* iteration_count(Model& model, IntegratorKind kind) { return iteration_count(model.implicit, model.solvers, kind); }

int iteration_count(const Model& model, IntegratorKind kind) { return iteration_count(model.method_defaults(), kind); }

double* residual_tolerance(ImplicitDef& implicit, SolverDefs& solvers, IntegratorKind kind) {
  return entry(kind).tolerance(implicit, solvers);
}

double* residual_tolerance(MethodSettings& s, IntegratorKind kind) { return residual_tolerance(s.implicit, s.solvers, kind); }

double* residual_tolerance(Model& model, IntegratorKind kind) { return residual_tolerance(model.implicit, model.solvers, kind); }

namespace analysis {
double predicted_limit(const StiffnessEstimate& e, IntegratorKind kind, const ImplicitDef& implicit) {
  if (!(e.w_max > 0.0) && !(e.c_max > 0.0)) return kInf;  // nothing stiff in the scene
  return entry(kind).info.linear_limit(e.w_max, e.c_max, implicit);
}
}  // namespace analysis

}  // namespace clothsim
