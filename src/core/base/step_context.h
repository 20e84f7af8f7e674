// What every phase of one step shares, built once per step (Box2D's b2StepContext): the step
// size and its inverse, how passes walk the springs, decided once per model, and the run's
// method settings. Stages take it instead of copying h into their own structs.
//
// The settings ride here rather than in the Workspace: every step function already takes the
// context, it is rebuilt from the Run at each step (so nothing of one run's settings can stay
// behind in scratch another run or a replay reuses), and what a step reads of its method is
// then visibly an argument of that step, as h is.
#pragma once

#include "method_settings.h"

namespace clothsim {

// How a pass over the springs walks them (springs/spring_layout.h, spring_path()).
enum class SpringPath {
  List,      // the scalar loop over the spring list: no grid, or a layout that does not cover it
  Families,  // every spring in a SIMD stencil family
  Mixed,     // SIMD families plus a scalar list of the springs in none
};

struct StepContext {
  double h = 0.0;      // s
  double inv_h = 0.0;  // 1/s
  SpringPath springs = SpringPath::List;
  const MethodSettings& settings;  // the run's (Run::settings()), outliving the step
};

inline StepContext make_step_context(double h, SpringPath springs, const MethodSettings& settings) {
  return StepContext{h, h > 0.0 ? 1.0 / h : 0.0, springs, settings};
}

}  // namespace clothsim
