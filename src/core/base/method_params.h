// The methods as a scene names them: which integrator (`integrator:`) and the iterative
// solvers' options (`xpbd:`, `projective_dynamics:`, `vbd:` blocks, docs/scenes.md). Plain
// values on the ground floor, so Model can carry them; everything else said about a method is
// its registry row (integrators/integrator.cpp). Defaults live here and nowhere else.
#pragma once

namespace clothsim {

enum class IntegratorKind {
  ExplicitEuler,    // x += h v_n; v += h a_n                        1 force eval
  SymplecticEuler,  // v += h a_n; x += h v_{n+1}                    1 force eval
  Midpoint,         // RK2 through the half-step state               2 force evals
  Rk4,              // classic Runge-Kutta 4 on (x, v)               4 force evals
  ImplicitEuler,    // backward Euler, Newton + PCG (or fixed point)  1 + solver work
  Xpbd,             // Macklin et al. 2016 compliant constraints        ~1 spring pass / iteration
  ProjectiveDynamics,  // Liu et al. 2013 local-global on Phi          pass + factored solve / iteration
  Vbd,              // Chen et al. 2024 vertex block descent on Phi    ~1 spring pass / iteration
  VelocityVerlet,   // Stormer-Verlet kick-drift-kick                1 force eval (reused)
  Yoshida4,         // Yoshida's 4th-order composition of three Verlet steps  3 force evals
  ImplicitMidpoint,  // the implicit family (integrators/implicit_family.h), each on
  Newmark,           // implicit_euler's Newton solve: Newton/CG work; newmark and
  GeneralizedAlpha,  // generalized_alpha carry an acceleration, bdf2 the step before
  Bdf2,
  Ros2,              // two-stage L-stable Rosenbrock, one matrix a step   2 force evals + 2 solves
  Bs3,              // Bogacki-Shampine 3(2) under error control         4 force evals a trial
  Dopri5,           // Dormand-Prince 5(4) under error control (FSAL)    6 a trial (7 the first)
  Rkf78,            // Fehlberg 7(8) under error control (order 8)       13 a trial
  Imex,             // Bridson et al. 2003: springs explicit, damping implicit  1 force eval + 2 solves
};

// A scene that names no integrator runs this one (the student report's code).
inline constexpr IntegratorKind kDefaultIntegrator = IntegratorKind::SymplecticEuler;

// Largest iteration count any solver block, --iterations or a lane's `:N` accepts.
constexpr int kMaxSolverIterations = 1000000;

// tolerance > 0: a step stops at the first iteration whose relative residual (solvers/
// solver_cache.h's ResidualStop) is at or below it, `iterations` then being a cap (a step that
// reaches the cap above it is NOT CONVERGED); 0: every step runs `iterations`.
struct XpbdDef {
  int iterations = 10;  // Gauss-Seidel sweeps over the constraints per step
  double tolerance = 0.0;
};

struct ProjectiveDynamicsDef {
  int iterations = 10;          // local-global iterations per step (Liu et al. 2013 use 10)
  double chebyshev_rho = 0.0;   // Wang 2015's spectral radius estimate; 0 = no acceleration
  double tolerance = 0.0;
};

struct VbdDef {
  int iterations = 10;         // Gauss-Seidel sweeps over the vertex colouring per step
  double chebyshev_rho = 0.0;  // Chen et al. 2024's accelerated iterations (Wang 2015's weights); 0 = off
  double tolerance = 0.0;
};

// Newmark's beta and gamma (Newmark 1959): x_{n+1} = x_n + h v_n + h^2 ((1/2 - beta) a_n +
// beta a_{n+1}), v_{n+1} = v_n + h ((1 - gamma) a_n + gamma a_{n+1}). The default is the
// trapezoidal rule (average acceleration): second order, energy-conserving on a linear
// spring, A-stable; gamma != 1/2 is first order, 2 beta < gamma only conditionally stable.
struct NewmarkDef {
  double beta = 0.25;
  double gamma = 0.5;
};

// Chung & Hulbert's (1993) generalized-alpha by its spectral radius at infinite w h: rho_inf in
// [0, 1]; 1 keeps every mode (the trapezoidal rule on a linear system), 0 annihilates the
// highest in one step. 0.5 is a common middle: high modes damped, low ones barely.
struct GeneralizedAlphaDef {
  double rho_inf = 0.5;
};

// The implicit family's parameters (integrators/implicit_family.h reads each in one place).
struct MethodDefs {
  NewmarkDef newmark;
  GeneralizedAlphaDef generalized_alpha;
};

// The adaptive pairs' error control (bs3, dopri5, rkf78): a trial step is accepted when every
// coordinate's error estimate e_i satisfies |e_i| <= atol + rtol (|y_i| + h |y'_i|) (Boost.Odeint's
// default_error_checker; y = (x in m, v in m/s)). Set by a lane's `:tol=` (both), `:rtol=`,
// `:atol=`; a lane that gives neither runs at kDefaultAdaptiveTolerance.
inline constexpr double kDefaultAdaptiveTolerance = 1e-6;
struct AdaptiveDef {
  double rtol = kDefaultAdaptiveTolerance;
  double atol = kDefaultAdaptiveTolerance;
};

struct SolverDefs {
  XpbdDef xpbd;
  ProjectiveDynamicsDef projective_dynamics;
  VbdDef vbd;
};

}  // namespace clothsim
