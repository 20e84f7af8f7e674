#include "study_run.h"

#include <cmath>

#include "core/integrators/integrator_kind.h"

namespace clothsim::analysis {

bool lands_on(double t, double dt) {
  const double n = t / dt, rounded = std::round(n);
  return rounded >= 1.0 && std::abs(n - rounded) <= 1e-9 * rounded;
}

StudyRun run_to(const Model& model, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop, const Sampling& sampling) {
  return run_to(model, model.method_defaults(), kind, dt, T, stop, sampling);
}

StudyRun run_to(const Model& model, const MethodSettings& settings, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop, const Sampling& sampling) {
  Run run(model, kind, dt, settings);
  if (stop) run.set_stop_check(stop);  // polled before every step: Ctrl-C answers at any step size
  const bool adaptive = integrator_info(kind).adaptive;
  bool going = true;
  for (std::size_t k = 0; going && k < sampling.times.size(); ++k) {
    const double t = sampling.times[k];
    if (t > T || !(adaptive || lands_on(t, dt))) continue;
    going = run.advance_to(t) && !run.stopped();
    if (going && sampling.at) sampling.at(k, run.state());
  }
  if (going) run.advance_to(T);
  StudyRun out;
  out.stopped = run.stopped();
  out.finished = !out.stopped && !run.diverged();
  out.divergence = run.divergence();
  out.totals = run.totals();
  out.final_state = run.state();
  return out;
}

}  // namespace clothsim::analysis
