#include "run_bounds.h"

#include <cstdio>

namespace clothsim {

std::string run_bounds_problem(double duration, double dt, double fps) {
  char text[200];
  const double steps = duration / dt;  // finite or +inf; never cast before the comparison
  if (!(steps <= kMaxSteps)) {
    std::snprintf(text, sizeof text,
                  "duration / dt = %g s / %g s = %.3g steps, more than the limit of %.0e (raise dt or "
                  "shorten the duration)",
                  duration, dt, steps, kMaxSteps);
    return text;
  }
  const double frames = duration * fps + 1.0;
  if (!(frames <= kMaxFrames)) {
    std::snprintf(text, sizeof text,
                  "duration x render.fps = %g s x %g = %.3g output frames, more than the limit of %.0e "
                  "(shorten the duration or lower render.fps)",
                  duration, fps, frames, kMaxFrames);
    return text;
  }
  return "";
}

}  // namespace clothsim
