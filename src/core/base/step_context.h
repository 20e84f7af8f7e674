// What every phase of one step shares, built once per step (Box2D's b2StepContext): the step
// size and its inverse, and how passes walk the springs, decided once per model. Stages take
// it instead of copying h into their own structs.
#pragma once

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
};

inline StepContext make_step_context(double h, SpringPath springs) {
  return StepContext{h, h > 0.0 ? 1.0 / h : 0.0, springs};
}

}  // namespace clothsim
