#include "barrier_terms.h"

#include <cmath>

#include "core/model/barrier_contacts.h"

namespace clothsim {

namespace {
const Eigen::Matrix3Xd& lag_point(const State& start, const StepForm& form) {
  return form.lag_x ? *form.lag_x : start.x;
}

// Where the barrier's pair terms are taken (StepForm::contact_stage): at the stage y and the
// pseudo-start, or both mapped to the step's end, x_n + (. - x_n) / theta.
struct ContactPoints {
  const Eigen::Matrix3Xd* y;
  const Eigen::Matrix3Xd* from;
  Eigen::Matrix3Xd y_end, from_end;
  double theta;
  ContactPoints(const State& start, const StepForm& form, const Eigen::Matrix3Xd& stage)
      : y(&stage), from(&start.x), theta(form.contact_stage) {
    if (theta == 1.0) return;
    const Eigen::Matrix3Xd& xn = lag_point(start, form);
    y_end = xn + (stage - xn) / theta;
    from_end = xn + (start.x - xn) / theta;
    y = &y_end;
    from = &from_end;
  }
};
}  // namespace

void add_barrier_potential(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                           Eigen::Matrix3Xd& gradient, PotentialValue& value) {
  const BarrierParams p = barrier_params(model);
  const double h = form.h;
  const ContactPoints at(start, form, y);
  for_each_barrier_pair(model, start.inv_mass, [&](const BarrierPair& pair) {
    const StepPairTerms t = step_pair_terms(model, p, pair, lag_point(start, form), *at.from, *at.y,
                                            form.damper_h / at.theta);
    if (!t.active) return;
    const double energy = at.theta == 1.0 ? t.energy : at.theta * t.energy;
    value.phi += energy;
    value.magnitude += std::abs(energy);
    gradient.col(pair.a) += h * t.gradient;
    if (pair.b >= 0) gradient.col(pair.b) -= h * t.gradient;
  });
}

void add_barrier_hessian(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                         SpringBlockMatrix& A) {
  const BarrierParams p = barrier_params(model);
  const Eigen::VectorXd& w = start.inv_mass;
  const ContactPoints at(start, form, y);
  const double h2 = at.theta == 1.0 ? form.h * form.h : form.h * form.h / at.theta;
  for_each_barrier_pair(model, w, [&](const BarrierPair& pair) {
    const StepPairTerms t = step_pair_terms(model, p, pair, lag_point(start, form), *at.from, *at.y,
                                            form.damper_h / at.theta);
    if (!t.active) return;
    for (const int i : {pair.a, pair.b}) {
      if (i < 0 || w[i] == 0.0) continue;
      A.diag[i] += h2 * t.hessian;
      A.diag_projected[i] += h2 * t.hessian;
    }
  });
  A.refresh_copies(SpringBlockMatrix::Refresh::Rest);  // the spring numbers are the assembly's
}

double barrier_line_bound(const Model& model, const State& start, const StepForm& form, const Eigen::Matrix3Xd& y,
                          const Eigen::Matrix3Xd& d) {
  const ContactPoints at(start, form, y);
  return barrier_step_bound(model, start.inv_mass, *at.y, (form.h / at.theta) * d, kBarrierKeep);
}

int barrier_feasible_start(const Model& model, const State& start, const StepForm& form, Eigen::Matrix3Xd& dv) {
  const double h = form.h, theta = form.contact_stage;
  const Eigen::Matrix3Xd guess = start.x + h * (start.v + dv);
  const ContactPoints at(start, form, guess);
  Eigen::Matrix3Xd y = *at.y;
  const int moved = push_out_of_colliders(model, start.inv_mass, y);
  if (moved > 0)  // only the moved particles' dv change (the others' would by rounding)
    for (int i = 0; i < model.num_particles; ++i) {
      if (y.col(i) == at.y->col(i)) continue;
      const Vec3 stage = theta == 1.0 ? Vec3(y.col(i)) : Vec3(lag_point(start, form).col(i) + theta * (y.col(i) - lag_point(start, form).col(i)));
      dv.col(i) = (stage - start.x.col(i)) / h - start.v.col(i);
    }
  return moved;
}

}  // namespace clothsim
