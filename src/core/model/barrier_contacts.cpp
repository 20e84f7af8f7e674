#include "barrier_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim {

BarrierParams barrier_params(const Model& model) {
  const double dhat = model.collision.barrier_distance;
  return {dhat, barrier_kappa_for_stiffness(model.collision.barrier_stiffness, dhat)};
}

double default_barrier_stiffness(double mean_particle_mass, const Vec3& gravity, double dhat) {
  const double g = gravity.norm() > 0.0 ? gravity.norm() : 9.8;  // standard gravity in a weightless scene
  return barrier_stiffness_for_weight(mean_particle_mass * g, dhat);
}

PointBarrier pair_barrier(const Model& model, const BarrierPair& pair, const Eigen::Matrix3Xd& x,
                          const BarrierParams& p, bool project_psd) {
  if (pair.b < 0) return plane_barrier(x.col(pair.a), model.ground.height + pair.r, p);
  return sphere_barrier(x.col(pair.a), x.col(pair.b), pair.r, p, project_psd);
}

namespace {

// Body i's share of a force F: F, or F / m_i for accelerations; nothing where immovable.
void apply(const Eigen::VectorXd& inv_mass, bool times_inverse_mass, int i, const Vec3& F, Eigen::Matrix3Xd& f) {
  const double w = inv_mass[i];
  if (w == 0.0) return;
  f.col(i) += times_inverse_mass ? Vec3(w * F) : F;
}

}  // namespace

void add_barrier_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                        const Eigen::VectorXd& inv_mass, bool times_inverse_mass, Eigen::Matrix3Xd& f) {
  const BarrierParams p = barrier_params(model);
  const double eps_v = model.collision.friction_velocity;
  for_each_barrier_pair(model, inv_mass, [&](const BarrierPair& pair) {
    if (!pair_within_reach(model, pair, x, p.dhat)) return;
    // The distance and normal alone: a force needs b' only (pair_barrier would form b and b'' too).
    Vec3 n = Vec3::UnitY();
    double d = x(1, pair.a) - model.ground.height - pair.r;
    if (pair.b >= 0) {
      const Vec3 rel = x.col(pair.a) - x.col(pair.b);
      const double rho = rel.norm();
      if (rho > 0.0) n = rel / rho;
      d = rho - pair.r;
    }
    const double b1 = barrier_derivative(d, p);
    Vec3 F = -b1 * n;  // on a; b receives -F
    if (pair.mu > 0.0) {
      const Vec3 rel = v.col(pair.a) - (pair.b >= 0 ? Vec3(v.col(pair.b)) : Vec3::Zero());
      const Vec3 vt = rel - rel.dot(n) * n;
      F += friction_force(vt, -b1, pair.mu, eps_v);
    }
    apply(inv_mass, times_inverse_mass, pair.a, F, f);
    if (pair.b >= 0) apply(inv_mass, times_inverse_mass, pair.b, -F, f);
  });
}

StepPairTerms step_pair_terms(const Model& model, const BarrierParams& p, const BarrierPair& pair,
                              const Eigen::Matrix3Xd& lag_x, const Eigen::Matrix3Xd& from_x,
                              const Eigen::Matrix3Xd& y, double h) {
  StepPairTerms out;
  const PointBarrier c = pair_within_reach(model, pair, y, p.dhat) ? pair_barrier(model, pair, y, p, true) : PointBarrier{};
  if (c.active()) {
    out.energy = c.energy;
    out.gradient = c.gradient;
    out.hessian = c.hessian;
    out.active = true;
  }
  if (pair.mu <= 0.0 || !pair_within_reach(model, pair, lag_x, p.dhat)) return out;
  const PointBarrier lag = pair_barrier(model, pair, lag_x, p, true);
  if (!lag.active()) return out;
  const auto moved = [&](int i) { return Vec3(y.col(i) - from_x.col(i)); };
  const Vec3 rel = moved(pair.a) - (pair.b >= 0 ? moved(pair.b) : Vec3::Zero());
  const Vec3 u = rel - rel.dot(lag.normal) * lag.normal;
  const FrictionTerm f = friction_potential(u, lag.normal, -barrier_derivative(lag.distance, p), pair.mu,
                                            model.collision.friction_velocity * h);
  out.energy += f.energy;
  out.gradient += f.gradient;
  out.hessian += f.hessian;
  out.active = true;
  return out;
}

double barrier_potential(const Model& model, const Eigen::Matrix3Xd& x) {
  if (!uses_barrier(model)) return 0.0;
  const BarrierParams p = barrier_params(model);
  double energy = 0.0;
  // Over every pair with a movable body at t = 0 (what can touch; the sum is a function of x).
  for_each_barrier_pair(model, model.initial_inv_mass, [&](const BarrierPair& pair) {
    energy += pair_barrier(model, pair, x, p, true).energy;
  });
  return energy;
}

int barrier_contact_count(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::VectorXd& inv_mass) {
  int count = 0;
  for_each_barrier_pair(model, inv_mass, [&](const BarrierPair& pair) {
    count += pair_within_reach(model, pair, x, model.collision.barrier_distance);
  });
  return count;
}

double smallest_barrier_distance(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::VectorXd& inv_mass) {
  double smallest = std::numeric_limits<double>::infinity();
  for_each_barrier_pair(model, inv_mass, [&](const BarrierPair& pair) {
    const double d = pair.b < 0 ? x(1, pair.a) - model.ground.height - pair.r
                                : (x.col(pair.a) - x.col(pair.b)).norm() - pair.r;
    smallest = std::min(smallest, d);
  });
  return smallest;
}

double barrier_step_bound(const Model& model, const Eigen::VectorXd& inv_mass, const Eigen::Matrix3Xd& x,
                          const Eigen::Matrix3Xd& dx, double keep) {
  double alpha = 1.0;
  for_each_barrier_pair(model, inv_mass, [&](const BarrierPair& pair) {
    if (pair.b < 0) {
      alpha = std::min(alpha, plane_step_bound(x(1, pair.a) - model.ground.height - pair.r, dx(1, pair.a), keep));
    } else {
      const Vec3 rel = x.col(pair.a) - x.col(pair.b), drel = dx.col(pair.a) - dx.col(pair.b);
      alpha = std::min(alpha, sphere_step_bound(rel, drel, pair.r, keep));
    }
  });
  return alpha;
}

int push_out_of_colliders(const Model& model, const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& x) {
  const double to = 0.5 * model.collision.barrier_distance;
  int moved = 0;
  for_each_barrier_pair(model, inv_mass, [&](const BarrierPair& pair) {
    if (pair.a >= model.num_particles || inv_mass[pair.a] == 0.0) return;
    if (pair.b < 0) {
      const double floor = model.ground.height + pair.r;
      if (x(1, pair.a) - floor > 0.0) return;
      x(1, pair.a) = floor + to;
    } else {
      const Vec3 rel = x.col(pair.a) - x.col(pair.b);
      const double rho = rel.norm();
      if (rho - pair.r > 0.0) return;
      const Vec3 n = rho > 1e-12 ? Vec3(rel / rho) : Vec3(Vec3::UnitY());
      x.col(pair.a) = x.col(pair.b) + (pair.r + to) * n;
    }
    ++moved;
  });
  return moved;
}

}  // namespace clothsim
