#include "solver_cache.h"

#include <cmath>

namespace clothsim {

void SolverCacheDeleter::operator()(SolverCache* cache) const { delete cache; }

SolverCache& solver_cache(Workspace& ws) {
  if (!ws.solvers) ws.solvers.reset(new SolverCache);
  return *ws.solvers;
}

double max_start_strain(const Model& model, const StepProblem& p) {
  double strain = 0.0;
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const double e = (p.start_length[k] - s.rest[k]) / s.rest[k];
    if (std::isnan(e)) return e;
    strain = std::max(strain, e);
  }
  return strain;
}

}  // namespace clothsim
