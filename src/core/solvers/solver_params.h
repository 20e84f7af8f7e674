// The iterative solvers' options as a scene gives them (`xpbd:`, `projective_dynamics:`,
// `vbd:` blocks, docs/scenes.md). Plain values; defaults live here and nowhere else.
#pragma once

namespace clothsim {

// Largest iteration count any solver block, --iterations or a lane's `:N` accepts.
constexpr int kMaxSolverIterations = 1000000;

struct XpbdDef {
  int iterations = 10;  // Gauss-Seidel sweeps over the constraints per step
};

struct ProjectiveDynamicsDef {
  int iterations = 10;          // local-global iterations per step (Liu et al. 2013 use 10)
  double chebyshev_rho = 0.0;   // Wang 2015's spectral radius estimate; 0 = no acceleration
};

struct VbdDef {
  int iterations = 10;         // Gauss-Seidel sweeps over the vertex colouring per step
  double chebyshev_rho = 0.0;  // Chen et al. 2024's accelerated iterations (Wang 2015's weights); 0 = off
};

struct SolverDefs {
  XpbdDef xpbd;
  ProjectiveDynamicsDef projective_dynamics;
  VbdDef vbd;
};

}  // namespace clothsim
