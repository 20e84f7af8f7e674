// Forces over the whole system: the springs, gravity and viscous air drag, evaluated at
// any (x, v) an integrator asks about. One call of accelerations() is one "force
// evaluation", the unit in which integrators' cost is compared.
#pragma once

#include <Eigen/Core>

#include "model.h"

namespace clothsim {

// f (3 x B) += the spring-damper forces of every spring at (x, v). Returns the largest
// strain (l - l0) / l0 over the springs at x (0 when none is stretched): the divergence check
// reads it off the step's first force evaluation instead of a second pass over the springs.
double accumulate_spring_forces(const Springs& springs, const Eigen::Matrix3Xd& x,
                              const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

// Total force (3 x B) at (x, v): springs, gravity m g on bodies with gravity, drag -c v on
// cloth particles. Immovable bodies (inv_mass 0) get zero force: they are filtered here.
// Returns the springs' largest strain at x, as accumulate_spring_forces.
double total_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                  const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& f);

// a = M^-1 f (3 x B): zero for immovable bodies, so they keep their velocity. Returns the
// springs' largest strain at x.
double accelerations(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                   const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& a);

}  // namespace clothsim
