// The backward-Euler step the three iterative solvers approximate, in end-of-step positions.
//
// implicit_euler minimises Phi(dv) (implicit/step_potential.h). With y = x_n + h (v_n + dv)
// the same function of the end positions is
//     G(y) = sum_i a_i/2 |y_i - yhat_i|^2 + sum_s [ks/2 (l - l0)^2 + kd/(2h) (l - ln)^2] + const,
//     a_i = m_i/h^2 + c/h (c: air drag, cloth only),
//     yhat_i = (m_i/h^2 (x_i + h v_i) + m_i g + (c/h) x_i) / a_i   (the inertial target),
// and grad_dv Phi = h grad_y G, so the gradient norm below is implicit_euler's residual
// M dv - h f in N s. Each spring term is one spring of stiffness ks + kd/h about the rest
// length (ks l0 + (kd/h) ln) / (ks + kd/h): what projective dynamics projects onto and what
// VBD's per-vertex Newton differentiates. Immovable bodies (inverse mass 0) end at
// x + h v: a_i = 0 and yhat_i is that position.
//
// Contacts with immovable colliders (the ground, kinematic spheres at their end-of-step
// centres) are one-sided: a particle within reach r + margin of a collider is `depth` inside.
// Each solver says how it enforces them (docs/integrators.md); the post-step response
// (collisions.h) acts after every one of them as after every integrator.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

struct Colliders {
  bool ground = false;
  double ground_reach = 0.0;       // m, height + margin
  double ground_friction = 0.0;
  double ground_restitution = 0.0;
  std::vector<Vec3> centre;        // (K) kinematic spheres' centres at the end of the step
  std::vector<Vec3> velocity;      // (K) their velocities, m/s
  std::vector<double> reach;       // (K) radius + margin, m
  std::vector<double> friction;    // (K)
  std::vector<double> restitution; // (K)
};

struct Penetration {
  Vec3 normal = Vec3::Zero();  // unit, out of the collider
  double depth = 0.0;          // m, > 0 inside the reach
  double friction = 0.0;       // Coulomb coefficient of the collider
  Vec3 collider_velocity = Vec3::Zero();
  double restitution = 0.0;    // of the collider
};

// Calls visit(Penetration) for every collider y lies inside the reach of.
template <class Visit>
void for_each_penetration(const Colliders& c, const Vec3& y, Visit&& visit) {
  if (c.ground && y.y() < c.ground_reach)
    visit(Penetration{Vec3::UnitY(), c.ground_reach - y.y(), c.ground_friction, Vec3::Zero(), c.ground_restitution});
  for (std::size_t k = 0; k < c.centre.size(); ++k) {
    const Vec3 d = y - c.centre[k];
    const double r = d.norm();
    if (r >= c.reach[k]) continue;
    const Vec3 n = r > 0.0 ? Vec3(d / r) : Vec3(Vec3::UnitY());
    visit(Penetration{n, c.reach[k] - r, c.friction[k], c.velocity[k], c.restitution[k]});
  }
}

// implicit_euler's held plane n . y = plane for a particle that starts at `from` and is at y
// (step_contacts.cpp's nearest_collider): the nearest collider at y; for a sphere, normal to
// the line from its end-of-step centre to `from`, at reach + kHeldClearance from the centre
// (step_contacts.h's sphere_held_plane, shared); for the ground, up, at its reach + kHeldClearance.
void held_plane(const Colliders& c, const Vec3& from, const Vec3& y, Vec3& normal, double& plane);

// implicit_euler's clearance beyond the reach (step_contacts.h's kContactClearance).
constexpr double kHeldClearance = 1e-9;  // m

// The deepest of the colliders at y: signed depth (negative outside every reach) and normal;
// depth -inf where there is no collider.
Penetration deepest_penetration(const Colliders& c, const Vec3& y);

struct StepProblem {
  double h = 0.0;
  Eigen::VectorXd weight;          // (B) a_i, kg/s^2; 0 where immovable
  Eigen::Matrix3Xd target;         // (3 x B) yhat, m
  Eigen::Matrix3Xd start;          // (3 x B) x_n, m
  std::vector<double> start_length;  // (S) ln, m
  std::vector<double> stiffness;     // (S) ks + kd/h, N/m
  std::vector<double> rest;          // (S) the blended rest length, m
  Colliders colliders;
};

void build_step_problem(const Model& model, const State& state, double h, StepProblem& p);

// G(y) without its constant, J (contacts not included).
double step_objective(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y);

// grad_y G at y (3 x B, zero on immovable bodies), N; returns |h grad_y G| (Phi's gradient
// norm, N s). One pass over the springs and one over the bodies.
double step_gradient(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y,
                     Eigen::Matrix3Xd& gradient);

// A particle this close to a collider's reach (or inside it) is in contact: the solvers hold
// contacts kHeldClearance beyond it, and an unconverged iterate may stop short by rounding.
constexpr double kContactBand = 1e-6;  // m

// A particle a solver holds on its held plane n . y >= plane (step_problem.h's held_plane).
struct HeldContact {
  int body = 0;
  Vec3 normal = Vec3::UnitY();
  double force = -1.0;  // N, the solver's own contact force along normal; < 0: read it off grad_y G
};

// Adds `body` to `held` when its end position y lies on its plane (within kContactBand).
inline void add_if_on_plane(int body, const Vec3& normal, double plane, const Vec3& y, std::vector<HeldContact>& held) {
  if (normal.dot(y) <= plane + kContactBand) held.push_back(HeldContact{body, normal});
}

// The iterative solvers' residual at y (docs/integrators.md, "Stopping on a residual"):
// |h r(y)| (N s, as implicit_euler's), r = grad_y G(y), the force imbalance over the movable
// bodies, r_i = a_i (y_i - yhat_i) - f_i(y), less each contact's reaction: the part of r_i
// pushing into the collider along the normal, for the particles in `held` (a solver's own, on
// their planes), else those within kContactBand of a collider's reach. `gradient` is scratch.
double step_residual(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y,
                     const std::vector<HeldContact>* held, Eigen::Matrix3Xd& gradient);

// The contact response the post-step pass (collisions.h) cannot give the particles a solver
// held on their planes, beyond the reach that pass acts within: after finish_step, for each,
// collisions.h's held_contact_response against its nearest kinematic collider, with the
// plane's push as the held impulse: h times the solver's contact force, or h max(0, n . grad_y G(y)),
// the force that holds y on the plane at G's minimiser, as implicit_euler's
// respond_to_step_contacts does. So friction acts on them. `gradient` is scratch.
void respond_to_held_contacts(const Model& model, const StepProblem& p, const Eigen::Matrix3Xd& y,
                              const std::vector<HeldContact>& held, Eigen::Matrix3Xd& gradient, State& state);

// Ends the step at y: v = (y - x_n) / h, x = y.
void finish_step(const StepProblem& p, const Eigen::Matrix3Xd& y, State& state);

}  // namespace clothsim
