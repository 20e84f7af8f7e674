// XPBD's constraint projections (Macklin, Mueller and Chentanez 2016, "XPBD: Position-Based
// Simulation of Compliant Constrained Dynamics"): pure functions of values.
#pragma once

#include "step_problem.h"

namespace clothsim {

// One compliant distance constraint C = |y_a - y_b| - l0 with compliance 1/ks and XPBD's
// damping beta = kd (eq. 26, gamma = alpha~ beta h = kd / (ks h)), multiplied through by
// ks h^2 so that ks = 0 (a pure damper) stays finite:
//     dlambda = (-ks h^2 C - lambda - kd h grad C . (y - x_n)) / ((ks h^2 + kd h) (w_a + w_b) + 1)
// with lambda the constraint's multiplier accumulated over the step (kg m). Moves y_a by
// w_a grad C dlambda and y_b by the opposite, and returns dlambda. grad C . (y - x_n) / h is the seed's damper rate
// (v_a - v_b) . u at the end of the step, with u at the current iterate.
double solve_distance_constraint(Vec3& ya, Vec3& yb, const Vec3& xa, const Vec3& xb, double wa,
                                 double wb, double rest, double ks, double kd, double h,
                                 double lambda);

// A contact as an inequality constraint with zero compliance: y is moved out along the normal
// by the depth, then the tangential displacement over the step relative to the collider is
// cancelled while it is below mu times that normal correction (static friction), and
// shortened by mu times it otherwise (kinetic): Macklin et al. 2019's "Small steps" friction.
void solve_contact_constraint(Vec3& y, const Vec3& x_start, double h, const Penetration& c);

}  // namespace clothsim
