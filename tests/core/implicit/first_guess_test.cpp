// Implicit Euler's first guess on hand-built histories of dv: each extrapolation is exact on the
// polynomials of its order, an extrapolation is taken only where it predicted the step
// kGuessAdvantage times closer than the last dv, the closer of two wins (the lower on a tie), a
// jump (a contact's onset) falls back to the last dv, and only the orders the history allows
// are ever chosen.
#include "core/implicit/first_guess.h"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include "core/model/state.h"

namespace clothsim {
namespace {

constexpr int kBodies = 7;

// A State whose last steps' dv are f(n), f(n - 1), f(n - 2) (count of them), with f(k) a
// 3 x B field of k.
template <class F>
State history(int n, int count, F f) {
  State s;
  Eigen::Matrix3Xd* slots[3] = {&s.implicit.dv, &s.implicit.dv_before, &s.implicit.dv_before2};
  for (int j = 0; j < count; ++j) *slots[j] = f(n - j);
  return s;
}

Eigen::Matrix3Xd field(double value) {
  Eigen::Matrix3Xd m(3, kBodies);
  for (int i = 0; i < kBodies; ++i) m.col(i) = Eigen::Vector3d(value, -2.0 * value + i, 0.5 * value * i);
  return m;
}

TEST(FirstGuess, EachExtrapolationIsExactOnItsOwnOrder) {
  const auto line = [](int k) { return field(1.0 + 0.25 * k); };
  const auto parabola = [](int k) { return field(1.0 + 0.25 * k - 0.125 * k * k); };
  const State l = history(5, 2, line), p = history(5, 3, parabola);
  Eigen::Matrix3Xd out;
  guess_through(DvHistory(l, kBodies), 1, out);
  EXPECT_LE((out - line(6)).cwiseAbs().maxCoeff(), 1e-14);
  guess_through(DvHistory(p, kBodies), 2, out);
  EXPECT_LE((out - parabola(6)).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(FirstGuess, TakesTheOrderThatPredictedTheStepAndTheLowerOnATie) {
  const auto line = [](int k) { return field(1.0 + 0.25 * k); };
  const auto parabola = [](int k) { return field(1.0 + 0.25 * k - 0.125 * k * k); };
  // On a line the line and the parabola both predict exactly: the line is taken.
  EXPECT_EQ(next_guess_order(DvHistory(history(5, 3, line), kBodies), line(6)), 1);
  // On a parabola only the parabola does.
  EXPECT_EQ(next_guess_order(DvHistory(history(5, 3, parabola), kBodies), parabola(6)), 2);
  // A constant dv: every order predicts it exactly, none is closer than the last dv.
  const auto constant = [](int) { return field(2.0); };
  EXPECT_EQ(next_guess_order(DvHistory(history(5, 3, constant), kBodies), constant(6)), 0);
}

TEST(FirstGuess, AnExtrapolationMustBeKGuessAdvantageTimesCloserThanTheLastDv) {
  // dv_n = 1, dv_{n-1} = 0: the last dv predicts 1, the line 2. A solution at 2 - e lies
  // e from the line and 1 - e from the last dv: the line only where (1 - e) / e > 4.
  const State s = history(1, 2, [](int k) { return field(static_cast<double>(k)); });
  const DvHistory past(s, kBodies);
  const double just_past = 1.0 / (1.0 + kGuessAdvantage);  // e where the ratio is exactly 4
  EXPECT_EQ(next_guess_order(past, field(2.0 - 0.9 * just_past)), 1);
  EXPECT_EQ(next_guess_order(past, field(2.0 - 1.1 * just_past)), 0);
}

TEST(FirstGuess, AJumpFallsBackToTheLastDv) {
  // A smooth history, then the solution jumps (a contact held from this step on): the
  // extrapolations predicted the smooth course and miss by more than the last dv does.
  const auto smooth = [](int k) { return field(1.0 + 0.01 * k); };
  EXPECT_EQ(next_guess_order(DvHistory(history(5, 3, smooth), kBodies), field(-3.0)), 0);
}

TEST(FirstGuess, OnlyTheOrdersTheHistoryAllows) {
  const auto parabola = [](int k) { return field(1.0 + 0.25 * k - 0.125 * k * k); };
  EXPECT_EQ(next_guess_order(DvHistory(history(5, 0, parabola), kBodies), parabola(6)), 0);
  EXPECT_EQ(next_guess_order(DvHistory(history(5, 1, parabola), kBodies), parabola(6)), 0);
  EXPECT_LE(next_guess_order(DvHistory(history(5, 2, parabola), kBodies), parabola(6)), 1);
  // A history of another body count is no history.
  EXPECT_EQ(DvHistory(history(5, 3, parabola), kBodies + 1).count, 0);
  // Nor are older steps without the newer ones.
  State gap = history(5, 3, parabola);
  gap.implicit.dv_before.resize(3, 0);
  EXPECT_EQ(DvHistory(gap, kBodies).count, 1);
}

}  // namespace
}  // namespace clothsim
