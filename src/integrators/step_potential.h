// Backward Euler as a minimisation: the equation implicit_euler solves, and its potential.
//
// The unknown is the velocity change dv (3 x B, zero on immovable bodies); the end of the
// step is v = v_n + dv, y = x_n + h v. implicit_euler solves the backward-Euler equations
//     r(dv) = M dv - h f(y, v) = 0,
//     f = sum over springs of -T u (T = ks (l - l0) + (kd / h) (l - ln), spring_force.h)
//         + m g on bodies with gravity - c v on cloth particles (air drag),
// with ln each spring's length at the start of the step. That is DESIGN.md's backward Euler
// with one change, in the dampers: their rate is the length's finite difference over the step,
// (l - ln) / h, rather than u . (v_a - v_b) at the end of it (the two agree to first order in
// h, and the first does not damp rigid rotation; spring_force.h). With it, r is the gradient of
//     Phi(dv) = 1/2 dv^T M dv + sum_s [1/2 ks (l - l0)^2 + kd / (2h) (l - ln)^2]
//               - h sum_i m_i g . v_i + (h c / 2) sum_cloth |v_i|^2
// (Gast, Schroeder, Stomakhin, Jiang and Teran 2015, "Optimization Integrator for Large Time
// Steps"): backward Euler's solution is a stationary point of Phi, which a line search on
// Phi can reach from any start, however large the step. Phi is bounded below (every term is
// but the linear gravity one, which the quadratic inertia outgrows), so a minimiser exists.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "model.h"
#include "state.h"

namespace clothsim {

// Each spring's length at x (S), written into `length`. Returns the largest strain
// (l - l0) / l0 of those lengths (0 when none is stretched), as the force pass does.
double spring_lengths(const Springs& springs, const Eigen::Matrix3Xd& x,
                      std::vector<double>& length);

struct PotentialValue {
  double phi = 0.0;        // J
  double magnitude = 0.0;  // J, what Phi's rounding scales with: its terms' absolute values, and
                           // each spring's |T| l (its energy squares a difference of lengths)
};

// Phi at dv and its gradient r (3 x B, zero on immovable bodies) for the step of size h from
// `start`; y (3 x B) receives the end-of-step positions x_n + h (v_n + dv). One pass over the
// springs and one over the bodies: the cost of one force evaluation.
PotentialValue step_potential(const Model& model, const State& start, double h,
                              const std::vector<double>& start_length, const Eigen::Matrix3Xd& dv,
                              Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient);

}  // namespace clothsim
