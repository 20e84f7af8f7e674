// Chung & Hulbert's (1993) generalized-alpha by rho_inf (method_params.h's GeneralizedAlphaDef):
// Newmark's updates with the equation of motion taken at t_{n+1-af} and the inertia at
// t_{n+1-am}, second order, its high-frequency damping set by rho_inf (implicit_family.h).
#include "implicit_family.h"

namespace clothsim {

StepStats generalized_alpha_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  return alpha_method_step(model, state, ctx, ws, IntegratorKind::GeneralizedAlpha,
                           generalized_alpha_method(generalized_alpha_params(ctx.settings)));
}

}  // namespace clothsim
