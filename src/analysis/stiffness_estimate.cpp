#include "analysis/stiffness_estimate.h"

#include <cmath>
#include <limits>
#include <vector>

namespace clothsim::analysis {

double StiffnessEstimate::dt_springs() const {
  return w_max > 0.0 ? 2.0 / w_max : std::numeric_limits<double>::infinity();
}

double StiffnessEstimate::dt_with_damping() const {
  const double rate = std::max(w_max, c_max);
  return rate > 0.0 ? 2.0 / rate : std::numeric_limits<double>::infinity();
}

StiffnessEstimate estimate_stiffness(const Model& model) {
  const int P = model.num_particles;
  // (P) Gershgorin row sums of the scalar Laplacians: |diagonal| + sum |off-diagonal|.
  std::vector<double> ks_row(P, 0.0), kd_row(P, 0.0);
  const auto free_particle = [&](int p) { return model.initial_inv_mass[p] > 0.0; };
  const Springs& s = model.springs;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const int a = s.a[i], b = s.b[i];
    // Each end's diagonal gets the spring; each end's off-diagonal gets it if the other end is free.
    const double ka = std::abs(s.ks[i]), da = std::abs(s.kd[i]);
    ks_row[a] += ka * (free_particle(b) ? 2.0 : 1.0);
    ks_row[b] += ka * (free_particle(a) ? 2.0 : 1.0);
    kd_row[a] += da * (free_particle(b) ? 2.0 : 1.0);
    kd_row[b] += da * (free_particle(a) ? 2.0 : 1.0);
  }
  StiffnessEstimate e;
  double w2 = 0.0;
  for (int p = 0; p < P; ++p) {
    if (!free_particle(p)) continue;  // pinned: no row in the free system
    const double inv_m = model.initial_inv_mass[p];
    const double row_w2 = ks_row[p] * inv_m;
    if (row_w2 > w2) w2 = row_w2, e.particle = p;
    e.c_max = std::max(e.c_max, (kd_row[p] + model.air_drag) * inv_m);
  }
  e.w_max = std::sqrt(w2);
  return e;
}

}  // namespace clothsim::analysis
