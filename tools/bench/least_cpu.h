// The least thread CPU time of `repeats` calls of f, in seconds (simulation.h's clock): the
// machine is shared, and the least is the run the other processes disturbed least. For the
// benches that time a phase themselves rather than through Google Benchmark's loop.
#pragma once

#include <algorithm>

#include "core/run/simulation.h"

namespace clothsim::bench {

template <class F>
double least_cpu_seconds(int repeats, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = thread_cpu_seconds();
    f();
    best = std::min(best, thread_cpu_seconds() - t0);
  }
  return best;
}

}  // namespace clothsim::bench
