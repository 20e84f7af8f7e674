#include "solver_cache.h"

#include <cmath>
#include <limits>

namespace clothsim {

void SolverCacheDeleter::operator()(SolverCache* cache) const { delete cache; }

SolverCache& solver_cache(Workspace& ws) {
  if (!ws.solvers) ws.solvers.reset(new SolverCache);
  return *ws.solvers;
}

ResidualStop::ResidualStop(const Model& model, const StepProblem& p, ResidualForm form, double tolerance,
                           const Eigen::Matrix3Xd& y0, Eigen::Matrix3Xd& scratch)
    : model_(model), p_(p), form_(form), tolerance_(tolerance), scratch_(scratch) {
  if (!active()) return;
  if (form_ == ResidualForm::StepPotential) initial_ = step_residual(model_, p_, y0, nullptr, scratch_);
  else scratch_ = y0, initial_ = -1.0;  // the first iteration's change sets the scale
}

bool ResidualStop::met(const Eigen::Matrix3Xd& y, const std::vector<HeldContact>* held) {
  if (!active()) return false;
  double r;
  if (form_ == ResidualForm::StepPotential) {
    r = step_residual(model_, p_, y, held, scratch_);
  } else {
    r = (y - scratch_).norm();
    scratch_ = y;
    if (initial_ < 0.0) initial_ = r;
  }
  // A first guess already in balance (nothing to do) is met by any iterate no worse.
  relative_ = initial_ > 0.0 ? r / initial_ : (r > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
  return relative_ <= tolerance_;
}

void ResidualStop::report(StepStats& stats) const {
  if (!active()) return;
  stats.residual = relative_;
  stats.converged = relative_ <= tolerance_;
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
