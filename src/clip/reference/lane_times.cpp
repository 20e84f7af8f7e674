#include "lane_times.h"

#include <algorithm>
#include <cmath>

namespace clothsim::clip {

std::int64_t landing_step(double target, double h, std::int64_t from) {
  const double goal = target - 1e-6 * h;  // Run::advance_to's tolerance
  std::int64_t k = std::max<std::int64_t>(from, static_cast<std::int64_t>(std::ceil(goal / h)));
  // (the products as the run forms its times, t = step h: the division's rounding corrected)
  while (static_cast<double>(k) * h < goal) ++k;
  while (k > from && static_cast<double>(k - 1) * h >= goal) --k;
  return k;
}

std::int64_t step_at(double t, double h) {
  const std::int64_t k = std::llround(t / h);
  return std::abs(static_cast<double>(k) * h - t) <= 1e-9 * h ? k : -1;
}

void hermite_positions(const std::vector<double>& xa, const std::vector<double>& va, double ta,
                       const std::vector<double>& xb, const std::vector<double>& vb, double tb, double t,
                       std::vector<double>& out) {
  const double dt = tb - ta, s = (t - ta) / dt, s2 = s * s, s3 = s2 * s;
  const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = (s3 - 2.0 * s2 + s) * dt;
  const double h01 = -2.0 * s3 + 3.0 * s2, h11 = (s3 - s2) * dt;
  out.resize(xa.size());
  for (std::size_t i = 0; i < xa.size(); ++i) out[i] = h00 * xa[i] + h10 * va[i] + h01 * xb[i] + h11 * vb[i];
}

std::vector<double> energy_samples_before(double t, double every, long& sample) {
  std::vector<double> times;
  for (double ts = static_cast<double>(sample) * every; ts < t - 1e-9; ts = static_cast<double>(++sample) * every)
    times.push_back(ts);
  return times;
}

}  // namespace clothsim::clip
