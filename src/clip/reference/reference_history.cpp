#include "reference_history.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace clothsim::clip {

ReferenceHistory::ReferenceHistory(const Model& model, const MethodSettings& settings, IntegratorKind kind,
                                   double dt)
    : model_(model), settings_(settings), kind_(kind), dt_(dt) {}

std::int64_t ReferenceHistory::keep_step(double t, double dt) {
  // A lane lands at or past t less 1e-6 of its step (lane_times.h), and the stand reads the
  // reference's step at or before that time: two steps of slack cover both and the rounding.
  return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor(t / dt)) - 2);
}

void ReferenceHistory::keep(const State& state) {
  if (!kept_.empty() && state.step <= kept_.back().step)
    throw std::logic_error("the reference kept step " + std::to_string(state.step) + " after step " +
                           std::to_string(kept_.back().step));
  kept_.push_back(state);
}

const State& ReferenceHistory::at(std::int64_t k) {
  if (kept_.empty() || k < kept_.front().step)
    throw std::logic_error("the reference was asked for step " + std::to_string(k) + ", before the states it kept");
  const double cpu_start = thread_cpu_seconds();
  while (kept_.size() > 1 && kept_[1].step <= k) kept_.pop_front();  // asked in increasing k: never again
  const State& from = kept_.front();
  if (!replaying_ || replay_.step > k || replay_.step < from.step) {
    replay_ = from;
    ws_ = Workspace{};  // as Run::last_finite_state replays: a step needs nothing of the workspace's past
    replaying_ = true;
  }
  while (replay_.step < k) step(model_, settings_, replay_, kind_, dt_, ws_);
  replay_cpu_ += thread_cpu_seconds() - cpu_start;
  return replay_;
}

}  // namespace clothsim::clip
