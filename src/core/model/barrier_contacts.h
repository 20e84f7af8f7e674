// The barrier contact model over a whole Model (collision.model: barrier): which pairs there
// are and their forces, energy, step bounds and a feasible start, over the kernels of
// barrier_kernels.h.
//
// Pairs: every particle against every sphere and the ground; every dynamic sphere against the
// ground; with collision.sphere_sphere, every two spheres (the sphere kernel with radius
// r1 + r2). A pair whose two bodies are both immovable (a pinned particle on a kinematic sphere)
// exerts nothing. The force on a sphere is the opposite of what it exerts (the pair's gradient
// with respect to the centre is minus that with respect to the particle), so a dynamic sphere
// and the cloth exchange momentum exactly.
#pragma once

#include <Eigen/Core>
#include <string>

#include "barrier_kernels.h"
#include "core/base/method_params.h"
#include "core/model/model.h"

namespace clothsim {

inline bool uses_barrier(const Model& model) { return model.collision.model == ContactModel::Barrier; }

// d-hat and kappa from the model's collision block (barrier_stiffness resolved by build_model).
BarrierParams barrier_params(const Model& model);

// The stiffness chosen when a scene sets none (barrier_kernels.h): the cloth's mean particle
// weight held at d-hat / 2. N/m.
double default_barrier_stiffness(double mean_particle_mass, const Vec3& gravity, double dhat);

// One pair: bodies a (a particle or a sphere) and b (a sphere body, or -1 for the ground), the
// reach r of b (its radius, or r_a + r_b between spheres; 0 for the ground), its friction mu.
struct BarrierPair {
  int a = 0, b = -1;
  double r = 0.0;
  double mu = 0.0;
};

// Calls visit(BarrierPair) for every pair of the model whose bodies are not both immovable.
template <class Visit>
void for_each_barrier_pair(const Model& model, const Eigen::VectorXd& inv_mass, Visit&& visit) {
  const int P = model.num_particles;
  const auto movable = [&](int i) { return inv_mass[i] != 0.0; };
  for (int s = 0; s < model.num_spheres; ++s) {
    const int b = model.sphere_body(s);
    for (int p = 0; p < P; ++p)
      if (movable(p) || movable(b)) visit(BarrierPair{p, b, model.sphere_radius[s], model.sphere_friction[s]});
  }
  if (model.has_ground) {
    for (int p = 0; p < P; ++p)
      if (movable(p)) visit(BarrierPair{p, -1, 0.0, model.ground.friction});
    for (int s = 0; s < model.num_spheres; ++s)
      if (movable(model.sphere_body(s)))
        visit(BarrierPair{model.sphere_body(s), -1, model.sphere_radius[s], model.ground.friction});
  }
  if (model.collision.sphere_sphere)
    for (int s = 0; s < model.num_spheres; ++s)
      for (int q = s + 1; q < model.num_spheres; ++q) {
        const int a = model.sphere_body(s), b = model.sphere_body(q);
        if (movable(a) || movable(b)) visit(BarrierPair{a, b, model.sphere_radius[s] + model.sphere_radius[q], 0.0});
      }
}

// The pairs body i belongs to (for a vertex's own terms: vbd), as for_each_barrier_pair.
template <class Visit>
void for_each_barrier_pair_of(const Model& model, const Eigen::VectorXd& inv_mass, int i, Visit&& visit) {
  const int P = model.num_particles;
  const auto movable = [&](int k) { return inv_mass[k] != 0.0; };
  if (i < P) {
    for (int s = 0; s < model.num_spheres; ++s) {
      const int b = model.sphere_body(s);
      if (movable(i) || movable(b)) visit(BarrierPair{i, b, model.sphere_radius[s], model.sphere_friction[s]});
    }
    if (model.has_ground && movable(i)) visit(BarrierPair{i, -1, 0.0, model.ground.friction});
    return;
  }
  for_each_barrier_pair(model, inv_mass, [&](const BarrierPair& pair) {
    if (pair.a == i || pair.b == i) visit(pair);
  });
}

// Whether the pair is within d-hat at x (no square root: the cheap test most pairs fail).
inline bool pair_within_reach(const Model& model, const BarrierPair& pair, const Eigen::Matrix3Xd& x, double dhat) {
  if (pair.b < 0) return x(1, pair.a) - model.ground.height - pair.r < dhat;
  const double reach = pair.r + dhat;
  return (x.col(pair.a) - x.col(pair.b)).squaredNorm() < reach * reach;
}

// The pair's barrier at positions x (3 x B): the ground's plane at height + r, or the sphere b.
PointBarrier pair_barrier(const Model& model, const BarrierPair& pair, const Eigen::Matrix3Xd& x,
                          const BarrierParams& p, bool project_psd);

// f (3 x B) += the barrier's forces and smoothed friction at (x, v), times the inverse mass
// where `times_inverse_mass` (accelerations); nothing on immovable bodies (inverse mass 0).
// Inside every force evaluation of the explicit methods.
void add_barrier_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                        const Eigen::VectorXd& inv_mass, bool times_inverse_mass, Eigen::Matrix3Xd& f);

// A pair's terms in a backward-Euler step's potential as functions of the end positions y
// (3 x B): the barrier at y and IPC's lagged friction, lambda = -b'(d) and the tangent plane
// taken at lag_x (the step's start x_n), on the tangential relative displacement y - from_x
// (x_n for backward Euler) over the friction's step h (the displacement is h times the
// velocity), with eps = eps_v h. Energy (J); gradient with respect to body a's end position (b's is minus it);
// Hessian, projected to PSD, for a's and b's diagonal blocks (the cross blocks are minus it).
struct StepPairTerms {
  double energy = 0.0;
  Vec3 gradient = Vec3::Zero();
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  bool active = false;  // within reach at y or in friction contact at x_n
};
StepPairTerms step_pair_terms(const Model& model, const BarrierParams& p, const BarrierPair& pair,
                              const Eigen::Matrix3Xd& lag_x, const Eigen::Matrix3Xd& from_x,
                              const Eigen::Matrix3Xd& y, double h);

// The barrier's potential at x, J (part of the potential energy the diagnostics print).
double barrier_potential(const Model& model, const Eigen::Matrix3Xd& x);

// Pairs within d-hat at x: the contacts a barrier step reports.
int barrier_contact_count(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::VectorXd& inv_mass);

// The smallest distance of any pair at x, m (+inf without pairs): a test's and the solvers' guard.
double smallest_barrier_distance(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::VectorXd& inv_mass);

// The largest alpha in [0, 1] with every pair's distance along x + alpha dx at least `keep`
// times its value at x (closed form per pair: barrier_kernels.h's step bounds).
double barrier_step_bound(const Model& model, const Eigen::VectorXd& inv_mass, const Eigen::Matrix3Xd& x,
                          const Eigen::Matrix3Xd& dx, double keep);

// Moves each movable particle of x that lies at or inside a collider (distance <= 0) out along
// the collider's normal to d-hat / 2: a feasible start for a solve (the barrier is infinite
// there). Returns how many were moved.
int push_out_of_colliders(const Model& model, const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& x);

}  // namespace clothsim
