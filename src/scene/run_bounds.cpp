#include "run_bounds.h"

#include <cstdio>
#include <cstdlib>
#include <utility>

namespace clothsim {

namespace {

std::string with_digits(double value, int digits) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

// An operand as the user wrote it: %g, or up to 10 digits where it takes more to read back
// exactly (duration 1.0000001 is not "1"); a computed step (stability's 1/2^k ranges) that
// needs more keeps %g's 6.
std::string operand(double value) {
  for (int digits = 6; digits <= 10; ++digits) {
    const std::string text = with_digits(value, digits);
    if (std::strtod(text.c_str(), nullptr) == value) return text;
  }
  return with_digits(value, 6);
}

// A count over its limit and the limit, written alike with as many digits as it takes for them
// to differ (3 at least): 1e7 + 1 frames against 1e7 reads "10000001 ... the limit of
// 10000000", not "1e+07 ... the limit of 1e+07".
std::pair<std::string, std::string> count_and_limit(double count, double limit) {
  for (int digits = 3; digits < 17; ++digits) {
    std::string c = with_digits(count, digits), l = with_digits(limit, digits);
    if (c != l) return {c, l};
  }
  return {with_digits(count, 17), with_digits(limit, 17)};
}

}  // namespace

std::string run_bounds_problem(double duration, double dt, double fps) {
  const double steps = duration / dt;  // finite or +inf; never cast before the comparison
  if (!(steps <= kMaxSteps)) {
    const auto [count, limit] = count_and_limit(steps, kMaxSteps);
    return "duration / dt = " + operand(duration) + " s / " + operand(dt) + " s = " + count +
           " steps, more than the limit of " + limit + " (raise dt or shorten the duration)";
  }
  // One frame at t = 0 and one per 1/fps s after it: the + 1 is counted, so it is shown.
  const double frames = duration * fps + 1.0;
  if (!(frames <= kMaxFrames)) {
    const auto [count, limit] = count_and_limit(frames, kMaxFrames);
    return "duration x render.fps + 1 = " + operand(duration) + " s x " + operand(fps) + " + 1 = " + count +
           " output frames, more than the limit of " + limit + " (shorten the duration or lower render.fps)";
  }
  return "";
}

}  // namespace clothsim
