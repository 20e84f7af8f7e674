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
  Bs3,              // Bogacki-Shampine 3(2) under error control         4 force evals a trial
  Dopri5,           // Dormand-Prince 5(4) under error control (FSAL)    6 a trial (7 the first)
  Rkf78,            // Fehlberg 7(8) under error control (order 8)       13 a trial
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
