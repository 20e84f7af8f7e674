// Newmark's method (Newmark 1959) with beta and gamma (method_params.h's NewmarkDef; the
// trapezoidal rule by default), on the Newton solve: the stage is x_{n+1} itself, c = beta,
// and the carried acceleration a_n (implicit_family.h derives the form and the history).
#include "implicit_family.h"

namespace clothsim {

StepStats newmark_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  return alpha_method_step(model, state, ctx, ws, IntegratorKind::Newmark, newmark_method(newmark_params(ctx.settings)));
}

}  // namespace clothsim
