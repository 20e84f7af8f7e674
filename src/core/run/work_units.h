// What a run cost, in a unit that does not depend on the machine or its load: spring-pass
// equivalents, one being one force evaluation (a pass over the springs and the bodies).
// Newton's other work is weighted by what it costs beside that pass, measured once on the
// drape's own 25 x 25 sheet (BENCHMARKS.md, "Work units"), so a compare matched on cost
// chooses the same steps on every machine and every run, and its frames are reproducible.
// CPU seconds stay the measured truth; this unit is what is counted and compared.
#pragma once

#include "simulation.h"

namespace clothsim {

// Spring-pass equivalents of one piece of a step's work.
struct WorkWeights {
  double force_eval = 1.0;    // a force or Phi evaluation: the unit itself
  double assembly = 0.0;      // a Newton matrix assembled (3x3 blocks per spring)
  double cg_jacobi = 0.0;     // a block-Jacobi PCG iteration: a block mat-vec and a 3x3 solve per body
  double cg_factored = 0.0;   // a factored PCG iteration: the mat-vec and two triangular solves
  double factorization = 0.0; // a sparse Cholesky factor built
  // (a solver's iteration: its registry row's passes_per_iteration, RunTotals)
};
const WorkWeights& work_weights();  // the calibrated table

// The run's work so far in spring-pass equivalents (force evaluations alone for the explicit
// family and the fixed point; Newton's assemblies, PCG iterations and factors added for
// implicit_euler; the iterations of xpbd, projective_dynamics and vbd, weighed by their rows).
double spring_passes(const RunTotals& totals, const WorkWeights& weights = work_weights());

}  // namespace clothsim
