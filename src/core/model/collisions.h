// Contacts under collision.model: projection (the course's, the default), resolved once per
// step after the integrator (never inside its stages). The barrier model: contact/.
//
// Detection: a particle is in contact with a sphere when |x - c| < r + margin, with the
// ground plane y = h when x_y < h + margin (the seed report's margin, 0.01 m by default).
//
// Response: the seed's 1-D collision formula applied to the normal components only,
//     v_a = (m_a u_a + m_b u_b + m_b C (u_b - u_a)) / (m_a + m_b),
// written in inverse masses w = 1/m, which is the same as an impulse along the normal n:
//     j = -(1 + C) (u_a - u_b) / (w_a + w_b),   v_a += w_a j n,   v_b -= w_b j n.
// So a pinned particle (w = 0) never moves and a kinematic sphere (w = 0) is never pushed,
// and what a dynamic sphere gains the cloth loses: momentum is conserved.
// The impulse is applied only while the bodies approach (u_a - u_b < 0); a particle already
// leaving keeps its velocity (the seed applies it always, which glues cloth to a sphere when
// C = 0). Tangential velocity is kept, less optional Coulomb friction (|j_t| <= mu |j|).
// Then the particle is projected to the surface plus margin (the sphere if the particle is
// pinned), so no particle is left inside a collider after a step.
#pragma once

#include "model.h"
#include "state.h"

namespace clothsim {

struct ContactCounts {
  int cloth_sphere = 0;
  int cloth_ground = 0;
  int sphere_sphere = 0;
  int sphere_ground = 0;
  int projected = 0;  // movable particles pushed out of an immovable collider (the ground, a
                      // kinematic sphere): for implicit_euler, contacts its solve missed
  int total() const { return cloth_sphere + cloth_ground + sphere_sphere + sphere_ground; }
};

// Normal impulse between two bodies (the formula above), pure. Returns j along n for body a
// (b receives -j). Zero when both are immovable or they are separating.
double contact_impulse(double u_a, double u_b, double w_a, double w_b, double restitution);

// Coulomb friction impulse along the tangential relative velocity vt (pure): the impulse on
// a that removes at most mu |jn| of tangential momentum, never reversing vt.
Vec3 friction_impulse(const Vec3& vt, double jn, double w_a, double w_b, double mu);

// The response of a particle a solver held on a collider's plane at the end of its step (pure;
// implicit_euler's step_contacts.h and the iterative solvers' step_problem.h): rel its velocity
// relative to the collider, n the plane's normal, w its inverse mass, `held` the normal impulse
// the constraint exerted (N s, >= 0). A separating normal velocity (the trace of a position
// correction) is removed, an approaching one reversed times the restitution, and Coulomb
// friction bounded by the whole normal impulse (restitution's and held's) acts on the
// tangential part. Returns the change of velocity.
Vec3 held_contact_response(const Vec3& rel, const Vec3& n, double w, double restitution, double friction,
                           double held);

// The projection above under collision.model: projection; under barrier nothing is resolved
// after the step (the barrier acted inside it, as a force or a term of Phi): only its contacts,
// the pairs within d-hat (count_barrier_contacts), are counted.
ContactCounts resolve_collisions(const Model& model, State& state);
ContactCounts count_barrier_contacts(const Model& model, const State& state);

}  // namespace clothsim
