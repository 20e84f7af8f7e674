// Backward Euler as a minimisation: the equation implicit_euler solves, and its potential.
//
// The unknown is the velocity change dv (3 x B, zero on immovable bodies); the end of the
// step is v = v_n + dv, y = x_n + h v. implicit_euler solves the backward-Euler equations
//     r(dv) = M dv - h f(y, v) = 0,
//     f = sum over springs of -T u (T = ks (l - l0) + (kd / h) (l - ln), spring_force.h)
//         + m g on bodies with gravity - c v on cloth particles (air drag),
// with ln each spring's length at the start of the step. That is the textbook backward Euler
// with one change, in the dampers: their rate is the length's finite difference over the step,
// (l - ln) / h, rather than u . (v_a - v_b) at the end of it (the two agree to first order in
// h, and the first does not damp rigid rotation; spring_force.h). With it, r is the gradient of
//     Phi(dv) = 1/2 dv^T M dv + sum_s [1/2 ks (l - l0)^2 + kd / (2h) (l - ln)^2]
//               - h sum_i m_i g . v_i + (h c / 2) sum_cloth |v_i|^2
// (Gast, Schroeder, Stomakhin, Jiang and Teran 2015, "Optimization Integrator for Large Time
// Steps"): backward Euler's solution is a stationary point of Phi, which a line search on
// Phi can reach from any start, however large the step. Phi is bounded below (every term is
// but the linear gravity one, which the quadratic inertia outgrows), so a minimiser exists.
// Under collision.model: barrier, Phi also holds the contacts' barrier and lagged friction at
// y (barrier_terms.h), and is +inf where a distance is <= 0.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "step_form.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

// The step's per-spring arrays (the start lengths here, the Newton blocks in sparse_system.h)
// are stored by the model's slot order (spring_layout.h: family positions, then the others;
// spring order itself when the layout does not cover the springs), so that the SIMD passes
// (potential_kernels.h) read them contiguously by family position.

// Each spring's length at x, by slot (slot_count(model.spring_layout, S) entries, zeros at
// slots without a spring), written into `length`: the family springs in SIMD, the others in
// the scalar loop. Returns the largest strain (l - l0) / l0 (0 when none is stretched; NaN
// when a length is NaN).
double step_lengths(const Model& model, const Eigen::Matrix3Xd& x, std::vector<double>& length);

// The scalar reference: each spring's length at x in spring order (S). The same lengths and
// strain, bit for bit, as step_lengths.
double spring_lengths(const Springs& springs, const Eigen::Matrix3Xd& x,
                      std::vector<double>& length);

struct PotentialValue {
  double phi = 0.0;        // J
  double magnitude = 0.0;  // J, what Phi's rounding scales with: its terms' absolute values, and
                           // each spring's |T| l (its energy squares a difference of lengths)
};

// Phi at dv and its gradient r (3 x B, zero on immovable bodies) for the step of form `form`
// (step_form.h; a bare h: backward Euler's) from `start` (x_s, v_s), with start_length the
// dampers' reference lengths by slot (step_lengths' l_n for backward Euler); y (3 x B)
// receives the end-of-step positions x_s + h (v_s + dv). One pass over the springs (the families in SIMD, then the
// others) and one over the bodies: the cost of one force evaluation.
//
// With end_length: also the springs' lengths at y by slot, what step_lengths(model, y,
// *end_length) would write, bit for bit (a step ending at this y starts the next from them),
// where the families hold every spring; otherwise end_length is cleared.
PotentialValue step_potential(const Model& model, const State& start, const StepForm& form,
                              const std::vector<double>& start_length, const Eigen::Matrix3Xd& dv,
                              Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& gradient,
                              std::vector<double>* end_length = nullptr);

// The largest strain of lengths by slot that step_potential wrote as end_length: what
// step_lengths returned when it wrote the same lengths.
double step_strain(const Model& model, const std::vector<double>& length);

// The scalar reference of step_potential: every spring in spring order, then the bodies. The
// same value and gradient to rounding (the order of the sums differs).
PotentialValue step_potential_scalar(const Model& model, const State& start, const StepForm& form,
                                     const std::vector<double>& start_length,
                                     const Eigen::Matrix3Xd& dv, Eigen::Matrix3Xd& y,
                                     Eigen::Matrix3Xd& gradient);

}  // namespace clothsim
