// What one step cost and how its solver fared: every step function returns one (the explicit
// family fills force_evals only). The ground floor of core: it includes nothing of core.
#pragma once

namespace clothsim {

struct StepStats {
  int force_evals = 0;        // calls of accelerations()/total_forces()
  int newton_iterations = 0;  // implicit_euler's Newton or fixed-point iterations; a solver's iterations
  int cg_iterations = 0;      // summed over the step's linear solves
  int factorizations = 0;     // implicit_euler: sparse Cholesky factors of the step's matrix
  int assemblies = 0;         // implicit_euler: Newton matrices assembled (reuse skips some)
  int factored_cg_iterations = 0;  // of cg_iterations, those preconditioned by the factor
  double residual = 0.0;      // final relative residual of the implicit solve
  bool converged = true;      // false when a solve stalled or hit its cap above tolerance
  double start_strain = 0.0;  // largest (l - l0) / l0 of the state the step started from, read
                              // off the step's first force evaluation (no extra spring pass)
  int contact_constraints = 0;  // implicit_euler: contacts held inside the solve this step
};

}  // namespace clothsim
