// One Newton solve of an implicit step's incremental potential, shared by implicit_euler and
// the implicit family (integrators/implicit_family.h): implicit_euler.cpp states the method
// (first guess, contacts held in the solve or the barrier, convergence), step_form.h the
// potential's form. The caller sets the dampers' reference lengths, solves, and then moves
// the state by its own update from the solution.
#pragma once

#include "implicit_cache.h"
#include "newton_solve.h"
#include "step_form.h"
#include "core/base/step_stats.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

// Spring lengths l_n at `state` by slot into c.start_length, from the last evaluation's end
// lengths where the state starts exactly there (the same lengths, bit for bit, without the
// pass). Returns their largest strain (the step's start strain).
double start_lengths(const Model& model, const State& state, ImplicitCache& c);

// Newton on the step of `form` from `start` (its x and v are the pseudo-start x_s, v_s; its
// inverse masses the step's), with the dampers' reference lengths in c.start_length. Leaves the
// solution in c (dv, its end positions y, the residual r at it, the held contacts), sets
// stats' converged, residual, iterations and contact count, and records the solver's memory
// (first guess, held set, matrix record) in start.implicit. `start` is otherwise unchanged.
// `cfg`: the run's Newton and CG settings (MethodSettings::implicit).
void solve_incremental(const Model& model, const ImplicitDef& cfg, State& start, const StepForm& form,
                       ImplicitCache& c, const NewtonTracer& trace, StepStats& stats);

}  // namespace clothsim
