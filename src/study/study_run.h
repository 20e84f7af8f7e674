// One bounded run of a study: a Run advanced to time T, stoppable (Ctrl-C) before any step
// (Run's stop check), with its cost measured both as wall time and as the CPU
// time of the thread that ran it (the figure that does not grow when other processes share
// the cores). A run that diverges stops there (Run does), which bounds every run of a sweep.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "core/model/diagnostics.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"
#include "core/run/simulation.h"
#include "core/model/state.h"

namespace clothsim::analysis {

struct StudyRun {
  bool finished = false;                 // reached T (false: diverged or stopped)
  bool stopped = false;                  // `stop` returned true before T
  std::optional<Divergence> divergence;  // set when the run diverged
  RunTotals totals;                      // steps, evaluations, wall and thread-CPU seconds
  State final_state;                     // the state at T (or where the run stopped)
};

// The times a run is measured at on its way to T (a work-precision study's errors over time),
// each handed to `at` with the run's state there. A fixed-step run is measured at the times it
// lands on (a whole number of its steps, within 1e-9) and passes the others; an adaptive pair
// or solve reaches every one (dense output on a smooth scene). `times` ascending, in (0, T].
struct Sampling {
  std::vector<double> times;
  std::function<void(std::size_t index, const State& state)> at;
};

// Whether a run at fixed step dt lands on time t: t / dt a whole number within 1e-9.
bool lands_on(double t, double dt);

// Runs `model` with `kind` at step `dt` under `settings` (a lane's; without them the model's
// own) until t >= T (Run::advance_to's rule: the last step may pass T by less than dt when dt
// does not divide T), measured on the way by `sampling`. `stop` is polled before every step.
StudyRun run_to(const Model& model, const MethodSettings& settings, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop = {}, const Sampling& sampling = {});
StudyRun run_to(const Model& model, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop = {}, const Sampling& sampling = {});

}  // namespace clothsim::analysis
