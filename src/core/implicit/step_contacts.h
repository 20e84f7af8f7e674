// Contacts held inside implicit_euler's solve.
//
// At a large step the post-step projection alone lets a particle end deep inside a sphere and
// then snaps it out, stretching stiff springs by the depth (on stiff.yaml at 1/60 s, 20 %).
// So the step's contacts with immovable colliders, the ground and kinematic spheres (whose
// end-of-step position is known: they move at a constant velocity through a step), are
// constraints of the minimisation: a held particle's end position lies on the collider's
// tangent plane at surface + margin, n . y = plane, and every Newton direction is filtered
// along n (velocity_filter.h). The tangent plane lies outside the sphere, so sliding along it
// never penetrates.
//
// The set is found as an active set: before the solve, the particles predicted to end inside
// a collider's reach (from the previous step's velocity change), and those the previous step
// held that are predicted to end within the margin band; during it, a free particle that an
// iterate takes inside a collider is taken in at once; after it, a held particle whose
// contact impulse r . n pulls towards the collider is let go (at most three times a step, so
// the rounds end), and the solve resumes from where it was. Then the
// seed's restitution response acts on the held particles' velocities (collisions.h), with
// friction bounded by the impulse the solve's constraint exerted.
//
// Under collision.model: barrier nothing is held (the sets stay empty): the contacts are
// terms of Phi instead (barrier_terms.h).
//
// Dynamic spheres are not constraints: their contacts exchange momentum, which the post-step
// response does (collisions.h). That response stays after every step as a safety net; it
// counts the particles it still has to push out (RunTotals::safety_projections).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/linear/velocity_filter.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

// Held particles sit this far beyond the detection distance, so the post-step response
// (which acts below it) does not count rounding as a missed contact.
constexpr double kContactClearance = 1e-9;  // m

// The plane n . y = plane a particle starting at `from` is held on against a sphere (its
// end-of-step centre and reach): n from the centre towards `from`, so a particle that would
// pass into the sphere is held on the side it came from; at reach + kContactClearance. The
// iterative solvers hold contacts with the same (solvers/step_problem.h's held_plane).
inline void sphere_held_plane(const Vec3& centre, double reach, const Vec3& from, Vec3& normal, double& plane) {
  const Vec3 out = from - centre;
  const double len = out.norm();
  normal = len > 1e-12 ? Vec3(out / len) : Vec3(Vec3::UnitY());
  plane = normal.dot(centre) + reach + kContactClearance;
}

struct StepContacts {
  VelocityFilter filter;          // (C) held bodies and their normals
  std::vector<double> plane;      // (C) n . y at the held position, m
  std::vector<std::int32_t> collider;  // (C) sphere index, or -1 for the ground
  std::vector<std::uint8_t> held;      // (P) 1 where a particle is held
  std::vector<std::uint8_t> held_before;  // (P) 1 where the last step held a particle
  std::vector<std::uint8_t> let_go;       // (P) how many times this step let a particle go
  std::vector<std::int32_t> near;         // scratch: the particles the last search's SIMD screen passed

  std::size_t size() const { return filter.size(); }
};

// The contacts predicted for the step of size h from `start`: particles whose predicted end
// position x + h (v + guess) lies inside the reach (r + margin) of the ground or a kinematic
// sphere, or, for those in start.implicit.held, within a further margin of it (guess: the
// previous step's dv, or none).
void predict_step_contacts(const Model& model, const State& start, double h,
                           const Eigen::Matrix3Xd* guess, StepContacts& contacts);

// Moves the held particles' dv so that their end positions lie on their planes.
void place_on_planes(const StepContacts& contacts, const State& start, double h,
                     Eigen::Matrix3Xd& dv);

// During a solve, at end positions y: takes in the free particles inside a collider's reach.
// Returns whether any was.
bool take_in_step_contacts(const Model& model, const State& start, double h,
                           const Eigen::Matrix3Xd& y, StepContacts& contacts);

// Lets go of held particles whose impulse pulls (r . n < 0, r the gradient at the iterate) and
// that were let go fewer than three times this step. Returns whether any was.
bool let_go_step_contacts(const Eigen::Matrix3Xd& gradient, StepContacts& contacts);
// After a converged solve at end positions y with gradient r (the contact impulses on held
// particles): lets go of held particles whose impulse pulls (let_go_step_contacts), then takes
// in free ones inside a collider. Returns whether the set changed.
bool update_step_contacts(const Model& model, const State& start, double h,
                          const Eigen::Matrix3Xd& y, const Eigen::Matrix3Xd& gradient,
                          StepContacts& contacts);

// The seed's restitution response and Coulomb friction on the held particles' end velocities
// (in `state`, after the step), relative to their colliders: a separating normal velocity
// (the trace of a position correction) is removed, an approaching one reversed times C_R;
// the friction cone is bounded by the normal impulse, the solve's r . n plus the restitution's.
void respond_to_step_contacts(const Model& model, const StepContacts& contacts,
                              const Eigen::Matrix3Xd& gradient, State& state);

}  // namespace clothsim
