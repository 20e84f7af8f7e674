// The shape of an implicit step's incremental potential: what the implicit family
// (integrators/implicit_family.h) changes of backward Euler's Phi (step_potential.h).
//
// Every method of the family takes its step as the minimiser over an end point y of
//     1/2 |y - x_hat|_M^2 + c h^2 E(y),
// a damper at the velocity v(y) = alpha (y - x_n) + v_offset, with its own x_hat, c and
// (alpha, v_offset). The solver's unknown stays dv, with
//     y = x_s + h_e (v_s + dv),   h_e = sqrt(c) h,   x_hat = x_s + h_e v_s,
// from a pseudo-start (x_s, v_s) the method chooses so that v(y) = (y - x_s) / damper_h,
// damper_h = 1 / alpha: then Phi(dv) = 1/2 |dv|^2_M + E(y) + ... is backward Euler's Phi of
// step h_e from (x_s, v_s) but for two numbers, and divided by h_e^2 it is the potential above.
//  - The dampers' rate is (l - l_ref) / damper_h (Phi's term kd / (2 damper_h) (l - l_ref)^2),
//    l_ref by slot: the method's velocity relation applied to the spring's own length (as
//    backward Euler's (l - l_n) / h is), so rigid rotation is not damped.
//  - Air drag acts at v(y) = (h_e / damper_h) (v_s + dv): Phi's term (drag_h c / 2) |v_s + dv|^2
//    with drag_h = h_e^2 / damper_h.
//  - IPC's lagged friction acts on the tangential displacement y - x_s, i.e. at velocity
//    (y - x_s) / damper_h (eps = eps_v damper_h), its normal and force lagged at lag_x.
//  - The barrier acts at the stage y, or, with contact_stage = theta < 1, at the step's end
//    x_n + (y - x_n) / theta where a method extrapolates its end from an earlier stage
//    (implicit midpoint: theta = 1/2): Phi's term theta b(y_end) (its y-gradient the barrier's
//    force at y_end), so the line search keeps the end point, not only the stage, outside
//    every collider. Friction goes with it (displacements and eps over theta).
// Backward Euler is h_e = damper_h = drag_h = h from (x_n, v_n), l_ref = l_n: a bare step
// converts to that form, so every call that means backward Euler still reads `h`.
#pragma once

#include <Eigen/Core>

namespace clothsim {

struct StepForm {
  double h = 0.0;         // s, h_e: y = x_s + h (v_s + dv); Phi's gradient is M dv - h f
  double damper_h = 0.0;  // s, 1 / alpha: the dampers' rate (l - l_ref) / damper_h
  double drag_h = 0.0;    // s, h^2 / damper_h: the drag term's factor (drag acts at v(y))
  // Where lagged friction takes its normal and force: x_n; null: the pseudo-start x_s (they
  // coincide for backward Euler).
  const Eigen::Matrix3Xd* lag_x = nullptr;
  // theta: the barrier's point is x_n + (y - x_n) / theta, x_n = lag_x (1: the stage y itself).
  double contact_stage = 1.0;

  StepForm() = default;
  StepForm(double step) : h(step), damper_h(step), drag_h(step) {}  // NOLINT: backward Euler's form
  StepForm(double step, double damper, double drag) : h(step), damper_h(damper), drag_h(drag) {}
};

}  // namespace clothsim
