#include "state.h"

#include "simulation.h"

namespace clothsim {

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

}  // namespace clothsim
