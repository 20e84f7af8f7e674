// The Verlet family: velocity Verlet and its symmetric compositions (Yoshida 1990).
//
// One velocity-Verlet (Stormer-Verlet, kick-drift-kick) step of size h:
//     v_{1/2} = v_n + h/2 a_n,   x_{n+1} = x_n + h v_{1/2},   v_{n+1} = v_{1/2} + h/2 a_{n+1},
// symplectic and time-reversible, order 2; for x'' = -w^2 x its step matrix has det 1 and is
// stable while w h < 2, as symplectic Euler's. Its last force pass is the next step's first
// (first same as last), so a step costs one force evaluation, kept in State::history.
//
// Where forces depend on velocity (the seed's dampers, drag, barrier friction), a_{n+1} needs
// v_{n+1}, which it defines. The pass is taken at the predicted v* = v_{1/2} + h/2 a_n: v* is
// O(h^2) from v_{n+1}, so the kick errs by O(h^3) and the step stays second order; it is no
// longer exactly symmetric, so a composition built on it keeps order 4 only where the forces
// are conservative (an undamped spring, tests/core/integrators/verlet_test.cpp) and falls to
// order 2 as the dampers grow (docs/integrators.md gives both measurements).
//
// Yoshida's fourth-order "triple jump": three Verlet steps of w1 h, w0 h, w1 h with
//     w1 = 1 / (2 - 2^(1/3)),  w0 = 1 - 2 w1 = -2^(1/3) / (2 - 2^(1/3))
// (Yoshida 1990, Forest & Ruth 1990): the middle step runs backwards. Three force passes a
// step; undamped it is stable while w h < 1.5734.
#pragma once

#include "integrator.h"

namespace clothsim {

// `n` velocity-Verlet steps of weights[k] * ctx.h in a row, the first kick reusing the
// history `kind` left when the state is still the one it left (StepHistory::continues).
StepStats verlet_composition(const Model& model, State& state, const StepContext& ctx, Workspace& ws,
                             IntegratorKind kind, const double* weights, int n);

// The step matrices on (u, u', a) for u'' + c u' + w^2 u = 0 (analysis::StepMatrix), a the
// carried force pass, as the steps above apply them, the predicted velocity included: what
// the registry's limits are read from. Undamped, a = -w^2 u always, and the (u, u') block is
// textbook Verlet's.
void velocity_verlet_matrix(double h, double w, double c, double m[9]);
void yoshida4_matrix(double h, double w, double c, double m[9]);

// Yoshida's weights, w1, w0, w1.
inline constexpr double kYoshidaW1 = 1.3512071919596578;   // 1 / (2 - 2^(1/3))
inline constexpr double kYoshidaW0 = -1.7024143839193155;  // 1 - 2 w1

}  // namespace clothsim
