// BDF2 on (x, v), the second-order backward differentiation formula:
//     x_{n+1} - 4/3 x_n + 1/3 x_{n-1} = 2h/3 v_{n+1},   v_{n+1} - 4/3 v_n + 1/3 v_{n-1} = 2h/3 a_{n+1},
// A-stable, L-stable (its |R| -> 0 as w h grows), order 2, dissipative but much less than
// backward Euler at a resolved step. It is backward Euler of step h_e = 2h/3 from the
// pseudo-start x~ = (4 x_n - x_{n-1})/3, v~ = (4 v_n - v_{n-1})/3 (c = 4/9), the dampers at BDF2's
// rate of each length, (l - l~)/h_e with l~ = (4 l_n - l_{n-1})/3 (implicit_family.h).
// It needs the step before: without it (the first step, after a projection contact, an event
// or any write to the state, or at another h) the step is one backward Euler step, which
// keeps the order (one step's O(h^2) error), and starts the history again.
#include "implicit_family.h"

#include "core/implicit/incremental_step.h"
#include "core/implicit/newton_kernels.h"

namespace clothsim {

StepStats bdf2_step(const Model& model, State& state, const StepContext& ctx, Workspace& ws) {
  constexpr IntegratorKind kKind = IntegratorKind::Bdf2;
  const double h = ctx.h;
  const ImplicitDef& cfg = ctx.settings.implicit;
  ImplicitCache& c = cache_for(model, cfg, ws);
  const NewtonTracer trace(ws);
  StepStats stats;
  StepHistory& hist = state.history;
  const bool continues = hist.continues(kKind, state) && hist.h == h;
  stats.start_strain = start_lengths(model, state, c);
  ws.x2 = state.x;  // x_n, v_n, l_n: the next step's step before
  ws.v2 = state.v;
  std::vector<double> length_n = c.start_length;
  if (!continues) {  // backward Euler from (x_n, v_n)
    solve_incremental(model, cfg, state, h, c, trace, stats);
    simd_finish_step(state.x.data(), state.v.data(), c.dv.data(), h, static_cast<std::size_t>(c.dv.size()));
  } else {
    const double he = 2.0 * h / 3.0;
    for (std::size_t k = 0; k < c.start_length.size(); ++k)
      c.start_length[k] = (4.0 * c.start_length[k] - hist.length_before[k]) / 3.0;
    ws.x1.noalias() = (4.0 * state.x - hist.x_before) / 3.0;
    ws.v1.noalias() = (4.0 * state.v - hist.v_before) / 3.0;
    StepForm form(he);
    form.lag_x = &state.x;
    family_solve(model, cfg, state, ws.x1, ws.v1, form, c, trace, stats);
    state.v.noalias() = ws.v1 + c.dv;            // v_{n+1} = v~ + dv
    state.x.noalias() = ws.x1 + he * state.v;    // x_{n+1} = x~ + h_e v_{n+1}
    move_immovable(ws.x2, ws.v2, h, state);
  }
  respond_to_family_contacts(model, 1.0, c, state);
  if (c.contacts.size() != 0) {
    hist.filled = false;  // a projection contact: the next step starts again
    return stats;
  }
  hist.x_before.swap(ws.x2);
  hist.v_before.swap(ws.v2);
  hist.length_before.swap(length_n);
  hist.h = h;
  hist.record(kKind, state);
  return stats;
}

}  // namespace clothsim
