// A method's settings, as one run carries them: the scene's blocks (`implicit:`, `xpbd:`,
// `projective_dynamics:`, `vbd:`) and what a lane's items override of them (`:N`, `:tol=`,
// `:rtol=`, `:atol=`, `:beta=`...). The Model keeps the scene's as its defaults
// (Model::method_defaults()); a Run starts from those, the lane changes its own copy
// (clip::lane_settings), and every step reads the run's through its StepContext. So two lanes
// of one scene run on one Model, whatever their iterations (Box2D's b2World_Step(world, dt,
// subStepCount): the iterations are arguments, not copies of the world).
#pragma once

#include "method_params.h"
#include "model_params.h"

namespace clothsim {

struct MethodSettings {
  ImplicitDef implicit;  // implicit_euler and the implicit family: Newton/CG, or the fixed point
  SolverDefs solvers;    // xpbd, projective_dynamics, vbd: iterations, tolerance, chebyshev_rho
  AdaptiveDef adaptive;  // bs3, dopri5, rkf78: the error control's rtol and atol
  MethodDefs methods;    // newmark's beta and gamma, generalized_alpha's rho_inf
};

}  // namespace clothsim
