// The implicit family: implicit_midpoint, newmark, generalized_alpha and bdf2, each one step of
// implicit_euler's Newton solve (implicit/incremental_step.h) on its own incremental potential
//     1/2 |y - x_hat|_M^2 + c h^2 E(y)
// plus its velocity update (Kane, Marsden, Ortiz and West 2000; Gast et al. 2015 for backward
// Euler). What each step changes of backward Euler's Phi is a StepForm and a pseudo-start
// (implicit/step_form.h): h_e = sqrt(c) h, the dampers' step 1/alpha where the method's
// velocity at the stage is v(y) = alpha (y - x_n) + v_offset, and the dampers' reference
// lengths, the same relation applied to each spring's length (so rigid rotation is never
// damped, as in implicit_euler). Per method (a_n: the carried acceleration):
//
//   method              stage y       c                      alpha          v_offset
//   implicit_midpoint   x_{n+1/2}     1/4                    2/h            0
//   newmark (beta, g)   x_{n+1}       beta                   g/(beta h)     (1 - g/beta) v_n + h (1 - g/(2 beta)) a_n
//   generalized_alpha   x_{n+1-af}    (1-af) beta/(1-am)     g/(beta h)     (1 - (1-af) g/beta) v_n + (1-af) h (1 - g/(2 beta)) a_n
//   bdf2                x_{n+1}       4/9                    3/(2h)         (x_{n-1} - x_n)/(2h)
//
// with x_hat = x_n + h/2 v_n (midpoint), x_n + h v_n + h^2 (1/2 - beta) a_n (newmark),
// x_n + (1-af) h v_n + (1-af) h^2 ((1/2 - beta) - beta am/(1-am)) a_n (generalized_alpha),
// (4 x_n - x_{n-1})/3 + 2h/3 (4 v_n - v_{n-1})/3 (bdf2). The trapezoidal rule is newmark's
// default (beta, g) = (1/4, 1/2): alpha = 2/h, v_offset = -v_n, i.e. v_{n+1} = 2 (x_{n+1} - x_n)/h - v_n.
// The dampers' rate on a spring of length l is alpha (l - l_n) + q_s, q_s the offset's
// relation on the length: A r_n + B h l''_n for v_offset = A v_n + B h a_n (r_n = u_n . (v_a -
// v_b), l''_n = u_n . (a_a - a_b) + |(v_a - v_b) - r_n u_n|^2 / l_n); (l_{n-1} - l_n)/(2h) for
// bdf2. Drag acts at v(y); IPC's friction at v(y), lagged at x_n (step_form.h).
//
// Generalized-alpha's parameters from rho_inf (Chung & Hulbert 1993): am = (2 rho - 1)/(rho + 1),
// af = rho/(rho + 1), g = 1/2 - am + af, beta = (1 - am + af)^2 / 4; rho_inf = 1 is am = af =
// 1/2, the trapezoidal rule on a linear system (evaluated at the midpoint).
//
// History (State::history, used only while the state is bit for bit the one the last step
// left: StepHistory::continues). newmark and generalized_alpha carry a_{n+1}; without it (the
// first step, or after a projection contact, a pin, unpin or keyframe event, or a write from
// outside) they re-initialise a_n = M^-1 f(x_n, v_n) from the current forces (one force pass).
// bdf2 carries x_{n-1}, v_{n-1}, l_{n-1} and h; without them (or at another h) its step is one
// backward Euler step. A step that held a contact in its solve (collision.model: projection)
// records no history, so the next one restarts; under the barrier nothing restarts.
//
// Contacts: held in the solve at the stage y (collision.model: projection, step_contacts.h),
// then the seed's response on the final velocities; or the barrier's terms of Phi at y.
// The stage y is feasible; x_{n+1} of implicit_midpoint and generalized_alpha is extrapolated
// from it and may end inside a collider, which the post-step projection then resolves (and
// counts: RunTotals::safety_projections).
#pragma once

#include "integrator.h"
#include "core/implicit/implicit_cache.h"
#include "core/implicit/newton_solve.h"
#include "core/implicit/step_form.h"

namespace clothsim {

// The method's parameters in a run's settings, each read in one place (the accessor); of a
// model, its scene's.
NewmarkDef newmark_params(const MethodSettings& settings);
GeneralizedAlphaDef generalized_alpha_params(const MethodSettings& settings);
inline GeneralizedAlphaDef generalized_alpha_params(const Model& model) {
  return generalized_alpha_params(model.method_defaults());
}

// A Newmark-type method in Chung & Hulbert's form: newmark is am = af = 0.
struct AlphaMethod {
  double am = 0.0, af = 0.0, beta = 0.25, gamma = 0.5;
};
AlphaMethod newmark_method(const NewmarkDef& p);
AlphaMethod generalized_alpha_method(const GeneralizedAlphaDef& p);

// One step of an AlphaMethod from `state`, its history kept under `kind`.
StepStats alpha_method_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws,
                            IntegratorKind kind, const AlphaMethod& method);

// The shared solve: the step of `form` from the pseudo-start (xs, vs) (3 x B, swapped in and
// back), reference lengths in c.start_length, the solver's memory and the inverse masses
// state's; `cfg` the run's Newton settings. Leaves the solution in c (incremental_step.h).
void family_solve(const Model& model, const ImplicitDef& cfg, State& state, Eigen::Matrix3Xd& xs,
                  Eigen::Matrix3Xd& vs, const StepForm& form, ImplicitCache& c, const NewtonTracer& trace,
                  StepStats& stats);

// The seed's contact response on the held particles' final velocities, the solve's impulses
// times `impulse` (dv_{n+1}/d(dv) of the method's update: the impulse over the whole step).
void respond_to_family_contacts(const Model& model, double impulse, ImplicitCache& c, State& state);

// Immovable bodies move at their velocity through a step, whatever the method: x = x_n + h v_n,
// v = v_n, from the step's start (x_n, v_n).
void move_immovable(const Eigen::Matrix3Xd& x_n, const Eigen::Matrix3Xd& v_n, double h, State& state);

// c.start_length (l_n by slot) becomes the dampers' reference lengths l_n - damper_h q_s for a
// velocity offset A v_n + Bh a_n (a: null when Bh = 0).
void shift_reference_lengths(const Model& model, const State& state, const Eigen::Matrix3Xd* a, double A,
                             double Bh, double damper_h, std::vector<double>& length);

}  // namespace clothsim
