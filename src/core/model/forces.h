// Forces over the whole system: the springs, gravity and viscous air drag, evaluated at
// any (x, v) an integrator asks about. One call of accelerations() is one "force
// evaluation", the unit in which integrators' cost is compared.
#pragma once

#include <Eigen/Core>

#include "core/base/body_terms.h"
#include "model.h"

namespace clothsim {

// f (3 x B) += the spring-damper forces of the model's springs at (x, v). Returns the largest
// strain (l - l0) / l0 over the springs at x (0 when none is stretched; NaN when a length is
// NaN): the divergence check reads it off the step's first force evaluation instead of a
// second pass over the springs. The grid's stencil families run in the SIMD kernel
// (spring_kernels.h), any other spring in the scalar loop below; a model whose layout does
// not cover its springs runs all of them in the scalar loop.
double accumulate_spring_forces(const Model& model, const Eigen::Matrix3Xd& x,
                                const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

// The scalar reference of the same pass over any spring list, in list order: what the SIMD
// kernel is tested against, and the path for springs in no family. Same return value.
double accumulate_spring_forces_scalar(const Springs& springs, const Eigen::Matrix3Xd& x,
                                       const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

// What body_terms() reads (body_terms.h), for this model and state.
BodyTermInputs body_term_inputs(const Model& model, const Eigen::Matrix3Xd& v, const Eigen::VectorXd& inv_mass,
                                bool times_inverse_mass);

// Total force (3 x B) at (x, v): springs, gravity m g on bodies with gravity, drag -c v on
// cloth particles, and under collision.model: barrier the contacts' barrier and smoothed
// friction (contact/barrier_contacts.h). Immovable bodies (inv_mass 0) get zero force: they are filtered here.
// Returns the springs' largest strain at x, as accumulate_spring_forces.
double total_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                  const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& f);

// a = M^-1 f (3 x B): zero for immovable bodies, so they keep their velocity. Returns the
// springs' largest strain at x.
double accelerations(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                   const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& a);

}  // namespace clothsim
