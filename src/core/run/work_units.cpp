#include "work_units.h"

namespace clothsim {

const WorkWeights& work_weights() {
  // BENCHMARKS.md, "Work units": each piece's time over one spring force pass, drape 25 x 25
  // (the solvers' iterations: "The iterative solvers", solver_bench at 25 x 25).
  static const WorkWeights weights{1.0, 2.7, 1.1, 7.7, 146.0};
  return weights;
}

double spring_passes(const RunTotals& totals, const WorkWeights& w) {
  const auto n = [](std::int64_t count) { return static_cast<double>(count); };
  const std::int64_t jacobi_cg = totals.cg_iterations - totals.factored_cg_iterations;
  return w.force_eval * n(totals.force_evals) + w.assembly * n(totals.assemblies) +
         w.cg_jacobi * n(jacobi_cg) + w.cg_factored * n(totals.factored_cg_iterations) +
         w.factorization * n(totals.factorizations) +
         totals.solver_iteration_passes * n(totals.solver_iterations);
}

}  // namespace clothsim
