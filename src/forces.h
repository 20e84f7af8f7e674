// Forces over the whole system: the springs, gravity and viscous air drag, evaluated at
// any (x, v) an integrator asks about. One call of accelerations() is one "force
// evaluation", the unit in which integrators' cost is compared.
#pragma once

#include <Eigen/Core>

#include "model.h"

namespace clothsim {

// f (3 x B) += the spring-damper forces of every spring at (x, v).
void accumulate_spring_forces(const Springs& springs, const Eigen::Matrix3Xd& x,
                              const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f);

// Total force (3 x B) at (x, v): springs, gravity m g on bodies with gravity, drag -c v on
// cloth particles. Immovable bodies (inv_mass 0) get zero force: they are filtered here.
void total_forces(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                  const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& f);

// a = M^-1 f (3 x B): zero for immovable bodies, so they keep their velocity.
void accelerations(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v,
                   const Eigen::VectorXd& inv_mass, Eigen::Matrix3Xd& a);

}  // namespace clothsim
