#include "state.h"

#include <cmath>
#include <cstring>

namespace clothsim {

void apply_due_actions(const Model& model, State& state) {
  // An action at time t_a is due once the clock has reached it; the tolerance keeps an
  // action at t = 0.3 from slipping a step because 3000 x 1e-4 rounds to 0.29999999.
  const double due = state.t + 1e-9 * (1.0 + std::abs(state.t));
  while (state.next_action < model.timeline.size() &&
         model.timeline[state.next_action].t <= due) {
    const TimedAction& act = model.timeline[state.next_action++];
    switch (act.kind) {
      case TimedAction::Kind::Pin:
        state.inv_mass[act.body] = 0.0;
        state.v.col(act.body).setZero();
        break;
      case TimedAction::Kind::Unpin:
        state.inv_mass[act.body] = 1.0 / model.mass[act.body];
        break;
      case TimedAction::Kind::SetVelocity:
        state.v.col(act.body) = act.velocity;
        break;
    }
  }
}

State initial_state(const Model& model) {
  State s;
  s.x = model.initial_x;
  s.v = model.initial_v;
  s.inv_mass = model.initial_inv_mass;
  s.t = 0.0;
  s.step = 0;
  s.next_action = 0;
  apply_due_actions(model, s);  // keyframes and events scheduled at t = 0
  return s;
}

namespace {
// Bitwise, with memcmp: what a carried force pass needs (the same bits evaluate to the same
// forces; -0.0 against 0.0 evaluates again), and several times faster than Eigen's
// element-by-element ==, which was most of velocity_verlet's cost over symplectic Euler's
// (BENCHMARKS.md, "The new families").
template <typename M>
bool same_bits(const M& a, const M& b) {
  return a.size() == b.size() && (a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0);
}
}  // namespace

bool StepHistory::continues(IntegratorKind kind, const State& s) const {
  return filled && owner == kind && x.cols() == s.x.cols() && same_bits(x, s.x) && same_bits(v, s.v) &&
         same_bits(inv_mass, s.inv_mass);
}

void StepHistory::record(IntegratorKind kind, const State& s) {
  owner = kind;
  filled = true;
  x = s.x;
  v = s.v;
  inv_mass = s.inv_mass;
}

}  // namespace clothsim
