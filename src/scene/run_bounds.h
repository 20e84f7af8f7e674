// The largest run clothsim accepts, checked at validation in floating point (no cast of an
// unbounded product to an integer, which is undefined past 2^63 and overflowed compare's int
// frame counter): a typo such as dt: 1e-12 or duration: 1e300 is refused in milliseconds
// instead of stepping for days or allocating a frame list that cannot fit.
//
// The limits are far above any run clothsim is for (the shipped scenes take at most 1e6
// steps and 300 frames): a billion steps of the 2-particle spring take about two minutes,
// of the 25 x 25 drape about a day; ten million frames are 93 hours of video at 30 fps.
#pragma once

#include <string>

namespace clothsim {

inline constexpr double kMaxSteps = 1e9;   // duration / dt
inline constexpr double kMaxFrames = 1e7;  // duration x fps + 1 output frames

// Why a run of `duration` s at step `dt` s with frames at `fps` is refused, or "" when it is
// within the limits: "duration / dt = 1 s / 1e-12 s = 1e+12 steps, more than the limit of 1e+09
// (...)", or "duration x render.fps + 1 = 10000 s x 1000 + 1 = 10000001 output frames, more than the
// limit of 10000000 (...)": the numbers with as many digits as it takes to differ from the limit.
std::string run_bounds_problem(double duration, double dt, double fps);

}  // namespace clothsim
