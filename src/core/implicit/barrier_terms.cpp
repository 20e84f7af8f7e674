#include "barrier_terms.h"

#include <cmath>

#include "core/contact/barrier_contacts.h"

namespace clothsim {

namespace {
const Eigen::Matrix3Xd& lag_point(const State& start, const StepForm& form) {
  return form.lag_x ? *form.lag_x : start.x;
}
}  // namespace

void add_barrier_potential(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                           Eigen::Matrix3Xd& gradient, PotentialValue& value) {
  const BarrierParams p = barrier_params(model);
  const double h = form.h;
  for_each_barrier_pair(model, start.inv_mass, [&](const BarrierPair& pair) {
    const StepPairTerms t = step_pair_terms(model, p, pair, lag_point(start, form), start.x, y, form.damper_h);
    if (!t.active) return;
    value.phi += t.energy;
    value.magnitude += std::abs(t.energy);
    gradient.col(pair.a) += h * t.gradient;
    if (pair.b >= 0) gradient.col(pair.b) -= h * t.gradient;
  });
}

void add_barrier_hessian(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                         SpringBlockMatrix& A) {
  const BarrierParams p = barrier_params(model);
  const Eigen::VectorXd& w = start.inv_mass;
  const double h2 = form.h * form.h;
  for_each_barrier_pair(model, w, [&](const BarrierPair& pair) {
    const StepPairTerms t = step_pair_terms(model, p, pair, lag_point(start, form), start.x, y, form.damper_h);
    if (!t.active) return;
    for (const int i : {pair.a, pair.b}) {
      if (i < 0 || w[i] == 0.0) continue;
      A.diag[i] += h2 * t.hessian;
      A.diag_projected[i] += h2 * t.hessian;
    }
  });
  A.refresh_copies(SpringBlockMatrix::Refresh::Rest);  // the spring numbers are the assembly's
}

double barrier_line_bound(const Model& model, const State& start, double h, const Eigen::Matrix3Xd& y,
                          const Eigen::Matrix3Xd& d) {
  return barrier_step_bound(model, start.inv_mass, y, h * d, kBarrierKeep);
}

int barrier_feasible_start(const Model& model, const State& start, double h, Eigen::Matrix3Xd& dv) {
  const Eigen::Matrix3Xd guess = start.x + h * (start.v + dv);
  Eigen::Matrix3Xd y = guess;
  const int moved = push_out_of_colliders(model, start.inv_mass, y);
  if (moved > 0)  // only the moved particles' dv change (the others' would by rounding)
    for (int i = 0; i < model.num_particles; ++i)
      if (y.col(i) != guess.col(i)) dv.col(i) = (y.col(i) - start.x.col(i)) / h - start.v.col(i);
  return moved;
}

}  // namespace clothsim
