// What the CLI tests read back from a run: a PNG's simulated time and the divergence `run`
// reports, shared by the run and compare tests (which hold one to the other).
#pragma once

#include <cstdio>
#include <string>
#include <utility>

#include "render/png_io.h"

namespace clothsim::testing {

// The "t" tEXt a PNG of a run carries (png_sequence_sink: the picture's simulated time); -1 if none.
inline double png_time(const std::string& path) {
  PngText text;
  read_png(path, &text);
  for (const auto& [key, value] : text)
    if (key == "t") return std::stod(value);
  return -1.0;
}

// {step, t} of "diverged at step N, t = X s" in run's stderr; {-1, -1} if it is not there.
inline std::pair<long, double> reported_divergence(const std::string& err) {
  long step = -1;
  double t = -1.0;
  const auto at = err.find("diverged at step ");
  if (at != std::string::npos) std::sscanf(err.c_str() + at, "diverged at step %ld, t = %lf", &step, &t);
  return {step, t};
}

}  // namespace clothsim::testing
