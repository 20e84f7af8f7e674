#include "analysis/study_run.h"

#include <algorithm>
#include <cmath>

namespace clothsim::analysis {

StudyRun run_to(const Model& model, IntegratorKind kind, double dt, double T,
                const std::function<bool()>& stop) {
  Run run(model, kind, dt);
  // Slices of about 1/64 of the run (at least one step each): frequent enough that Ctrl-C
  // answers within a second on the longest reference run, rare enough to cost nothing.
  const double steps = std::ceil(T / dt - 1e-9);
  const int slices = static_cast<int>(std::clamp(steps, 1.0, 64.0));
  StudyRun out;
  for (int k = 1; k <= slices; ++k) {
    if (stop && stop()) {
      out.stopped = true;
      break;
    }
    // Intermediate targets need not be multiples of dt: advance_to passes them by less than
    // a step and the next slice carries on; only the last target, T itself, is exact.
    const double target = k == slices ? T : T * static_cast<double>(k) / slices;
    if (!run.advance_to(target)) break;
  }
  out.finished = !out.stopped && !run.diverged();
  out.divergence = run.divergence();
  out.totals = run.totals();
  out.final_state = run.state();
  return out;
}

}  // namespace clothsim::analysis
