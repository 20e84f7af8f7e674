// Yoshida's fourth-order symplectic composition: three velocity-Verlet steps of w1 h, w0 h,
// w1 h, the middle one backwards (verlet.h gives the weights and where order 4 holds).
#include "verlet.h"

namespace clothsim {

StepStats yoshida4_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  static constexpr double kWeights[] = {kYoshidaW1, kYoshidaW0, kYoshidaW1};
  return verlet_composition(model, state, ctx, ws, IntegratorKind::Yoshida4, kWeights, 3);
}

}  // namespace clothsim
