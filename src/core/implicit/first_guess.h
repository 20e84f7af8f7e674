// Implicit Euler's first guess for a step's velocity change dv (implicit_euler.cpp): the last
// step's dv, or the polynomial through the last steps' dv extrapolated one step, the line
// 2 dv_n - dv_{n-1} or the parabola 3 dv_n - 3 dv_{n-1} + dv_{n-2}. Which one a step takes is
// judged at the end of the step before: each order's prediction of that step is compared with
// its solution (quantities the step has already paid for, so the choice is judged, never
// assumed).
//
// An extrapolation is taken only where it predicted the last step kGuessAdvantage times closer
// than the last dv did, and then the closer of the two (the lower order on a tie). At small
// steps they win by far: on the drape at 1e-4 s the median relative residual Newton starts at
// is about 1e-3 from the last dv, 5.5e-6 from the line and 1.7e-6 from the parabola (16 % fewer
// Newton and 26 % fewer CG iterations than with the line alone over the first second at
// 25 x 25, 12 % and 24 % over 0.3 s at 64 x 64). At one step per frame, where Phi may have
// several minima and the guess decides which one Newton finds, they win less often (7-43 % of
// the steps on the drape and stiff.yaml from 1/240 to 1/30 s) and the iterations barely moved;
// in a collision they overshoot, and the plain dv wins. Higher orders were tried: the cubic
// through four steps amplifies each step's solve error 15 times (the parabola 7, the line 3) and
// took more Newton iterations than the parabola.
#pragma once

#include <Eigen/Core>

#include "core/model/state.h"

namespace clothsim {

inline constexpr double kGuessAdvantage = 4.0;
inline constexpr int kMaxGuessOrder = 2;

// The last steps' dv, newest first (dv_n, dv_{n-1}, dv_{n-2}), as many as the State holds
// for B bodies (0 .. 3, each present only with the newer ones).
struct DvHistory {
  const Eigen::Matrix3Xd* dv[kMaxGuessOrder + 1] = {nullptr, nullptr, nullptr};
  int count = 0;
  DvHistory(const State& state, int B);
};

// The polynomial of `order` (1 or 2, below past.count) through the last order + 1 steps' dv,
// extrapolated one step.
void guess_through(const DvHistory& past, int order, Eigen::Matrix3Xd& out);

// The guess order the next step takes, given this step's solution dv and the history it
// started from: 0 (the last dv), 1 (the line) or 2 (the parabola), at most past.count - 1.
int next_guess_order(const DvHistory& past, const Eigen::Matrix3Xd& dv);

}  // namespace clothsim
