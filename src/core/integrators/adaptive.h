// The adaptive lanes: embedded explicit Runge-Kutta pairs under error control, the methods
// scientific users pick by tolerance (SciPy's RK45/DOP853, SciML's Tsit5/Vern7, Odeint's
// dopri5). Each is Boost.Odeint's controlled stepper on the engine's ODE y = (x, v),
// y' = (v, a(x, v)), the accelerations() every explicit integrator calls:
//
//   bs3     Bogacki & Shampine 1989, 3(2): 4 stages (the 4th is FSAL in the paper; Odeint's
//           generic pair evaluates it afresh: 4 force evaluations a trial, honestly counted)
//   dopri5  Dormand & Prince 1980, 5(4), FSAL: 6 force evaluations a trial after the first
//   rkf78   Fehlberg 1968, 7(8): 13 force evaluations a trial; Odeint advances the 8th-order
//           solution (explicit_error_generic_rk<13, 8, 8, 7>), the 7th estimates the error
//
// A trial step of size h is accepted when every coordinate's error estimate e_i satisfies
// |e_i| <= atol + rtol (|y_i| + h |y'_i|) (Odeint's default_error_checker); rejected, h
// shrinks and the step is tried again; accepted, the controller proposes the next h. A step
// never crosses a timeline event: it is shortened to land on it, and the step after resumes
// with the size the controller proposed before shortening. Targets (a frame, a sheet column, a
// study's sample time) are Run's: on a smooth scene the steps cross them and the state there is
// a side step of the pair (dense output, simulation.h); under projection the steps land on them.
//
// Contacts. The barrier (collision.model: barrier) is a force inside a(x, v): the pair sees it
// and its error control holds. Projection contacts (the course's model) move particles after
// each accepted step, outside the ODE: the controller never sees that jump, so the tolerance
// bounds the error between contacts only; after a step whose projection moved a particle the
// pair restarts from the projected state (FSAL's stored derivative recomputed), as it does
// after an event (RunTotals::projected_steps counts them; summaries say so).
//
// As fixed-step methods (step() at a given h, a registry row's step function), each is its
// pair's higher-order solution without the error estimate: bs3 order 3, dopri5 order 5, rkf78
// order 8.
#pragma once

#include <cstdint>
#include <memory>

#include "core/base/step_context.h"
#include "core/base/step_stats.h"
#include "core/base/workspace.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

StepStats bs3_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats dopri5_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);
StepStats rkf78_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws);

// One accepted step of an adaptive pair, or why there is none.
struct AdaptiveStep {
  double h = 0.0;                // s, the step taken (shortened to land on `limit`, perhaps)
  std::int64_t force_evals = 0;  // over every trial, the rejected ones too
  std::int64_t rejected = 0;     // trials the error control refused
  double start_strain = 0.0;     // the largest strain of the state the step started from
  bool failed = false;           // the step size fell below what time can resolve
};

class AdaptiveStepper {
 public:
  // `control` the run's error control (MethodSettings::adaptive); `first_h` the first trial
  // step (a lane's @STEP, else the scene's dt).
  AdaptiveStepper(const Model& model, IntegratorKind kind, const AdaptiveDef& control, double first_h);
  ~AdaptiveStepper();
  // Advances `state` (x, v, t; not step) by one accepted step, landing exactly on `limit` when
  // the step would cross it. Collisions and events are the caller's (Run's).
  AdaptiveStep step(State& state, double limit);
  // The state was changed outside the ODE (a projection, an event): FSAL's stored derivative
  // is stale, so the next trial evaluates the right-hand side afresh.
  void restart();
  double proposed_step() const;  // s, the h the next trial starts from

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim
