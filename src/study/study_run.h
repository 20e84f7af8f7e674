// One bounded run of a study: a Run advanced to time T, stoppable (Ctrl-C) before any step
// (Run's stop check), with its cost measured both as wall time and as the CPU
// time of the thread that ran it (the figure that does not grow when other processes share
// the cores). A run that diverges stops there (Run does), which bounds every run of a sweep.
#pragma once

#include <functional>
#include <optional>

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

// Runs `model` with `kind` at step `dt` under `settings` (a lane's; without them the model's
// own) until t >= T (Run::advance_to's rule: the last step may pass T by less than dt when dt
// does not divide T). `stop` is polled before every step.
StudyRun run_to(const Model& model, const MethodSettings& settings, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop = {});
StudyRun run_to(const Model& model, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop = {});

}  // namespace clothsim::analysis
