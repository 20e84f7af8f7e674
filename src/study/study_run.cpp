#include "study_run.h"

namespace clothsim::analysis {

StudyRun run_to(const Model& model, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop) {
  return run_to(model, model.method_defaults(), kind, dt, T, stop);
}

StudyRun run_to(const Model& model, const MethodSettings& settings, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop) {
  Run run(model, kind, dt, settings);
  if (stop) run.set_stop_check(stop);  // polled before every step: Ctrl-C answers at any step size
  run.advance_to(T);
  StudyRun out;
  out.stopped = run.stopped();
  out.finished = !out.stopped && !run.diverged();
  out.divergence = run.divergence();
  out.totals = run.totals();
  out.final_state = run.state();
  return out;
}

}  // namespace clothsim::analysis
