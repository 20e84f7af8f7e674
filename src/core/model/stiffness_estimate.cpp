#include "stiffness_estimate.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <utility>
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
  // The barrier: a spring to a fixed collider on each particle's diagonal, of its stiffness at
  // d-hat / 2 (where a particle resting under its weight sits with the default stiffness).
  const double contact = model.collision.model == ContactModel::Barrier ? model.collision.barrier_stiffness : 0.0;
  double w2 = 0.0;
  for (int p = 0; p < P; ++p) {
    if (!free_particle(p)) continue;  // pinned: no row in the free system
    const double inv_m = model.initial_inv_mass[p];
    const double row_w2 = (ks_row[p] + contact) * inv_m;
    if (row_w2 > w2) w2 = row_w2, e.particle = p;
    e.c_max = std::max(e.c_max, (kd_row[p] + model.air_drag) * inv_m);
  }
  e.w_max = std::sqrt(w2);
  return e;
}

namespace {

// Whether |R(z)| <= 1 for R(z) = 1 + S(z), S(z) = sum_{m >= 1} a[m] z^m. Written as
// 2 Re S + |S|^2 <= 0 so the 1 never enters: near z = 0 on the imaginary axis, |R|^2 - 1 is
// of order |z|^4 (midpoint) and would vanish in rounding against the 1.
bool inside(const std::vector<double>& a, std::complex<double> z) {
  std::complex<double> s = 0.0, zm = 1.0;
  for (std::size_t m = 1; m < a.size(); ++m) {
    zm *= z;
    s += a[m] * zm;
  }
  return 2.0 * s.real() + std::norm(s) <= 0.0;
}

// The fastest mode's two roots l of l^2 + c l + w^2 = 0.
std::pair<std::complex<double>, std::complex<double>> mode_roots(double w, double c) {
  const std::complex<double> root = std::sqrt(std::complex<double>(c * c - 4.0 * w * w, 0.0));
  return {0.5 * (-c + root), 0.5 * (-c - root)};
}

// The largest stable h: scanned down from |h l| = 4 (beyond every region here) in steps of
// 0.1 %, then bisected. Searching from the top finds the region's far edge, which is the
// limit the step cannot pass; 0 when no h with |h l| >= 1e-6 is stable (explicit Euler and
// midpoint on an undamped mode).
template <class Stable>
double largest_stable_step(Stable stable, double fastest) {
  const double step = 1.001;
  for (double h = 4.0 / fastest; h * fastest >= 1e-6; h /= step) {
    if (!stable(h)) continue;
    double lo = h, hi = h * step;  // stable, unstable
    for (int i = 0; i < 60 && hi - lo > 1e-12 * lo; ++i) (stable(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
    return lo;
  }
  return 0.0;
}

}  // namespace

// Largest h with h l inside R's region for both roots l of the mode.
double polynomial_limit(const std::vector<double>& a, double w, double c) {
  // (Not a structured binding: C++17 lets no lambda capture one, which clang enforces.)
  const std::pair<std::complex<double>, std::complex<double>> l = mode_roots(w, c);
  return largest_stable_step([&](double h) { return inside(a, h * l.first) && inside(a, h * l.second); },
                             std::max(std::abs(l.first), std::abs(l.second)));
}

namespace {
// The largest |root| of a row-major 3 x 3 matrix's characteristic polynomial
// l^3 - t l^2 + q l - d (t the trace, q the principal 2 x 2 minors' sum, d the determinant),
// by Durand-Kerner iteration: the three roots at once, complex ones included. Infinity for a
// matrix with a non-finite entry.
double spectral_radius3(const double m[9]) {
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(m[i])) return std::numeric_limits<double>::infinity();
  const double t = m[0] + m[4] + m[8];
  const double q = m[0] * m[4] - m[1] * m[3] + m[0] * m[8] - m[2] * m[6] + m[4] * m[8] - m[5] * m[7];
  const double d = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                   m[2] * (m[3] * m[7] - m[4] * m[6]);
  using C = std::complex<double>;
  const auto p = [&](C l) { return ((l - t) * l + q) * l - d; };
  const double scale = 1.0 + std::abs(t) + std::abs(q) + std::abs(d);
  C r[3] = {C(0.4, 0.9) * scale, C(0.4, 0.9) * C(0.4, 0.9) * scale, C(0.4, 0.9) * C(0.4, 0.9) * C(0.4, 0.9) * scale};
  for (int it = 0; it < 500; ++it) {
    double moved = 0.0;
    for (int k = 0; k < 3; ++k) {
      C den = 1.0;
      for (int j = 0; j < 3; ++j)
        if (j != k) den *= r[k] - r[j];
      const C delta = den == C(0.0) ? C(1e-12 * scale) : p(r[k]) / den;
      r[k] -= delta;
      moved = std::max(moved, std::abs(delta));
    }
    if (moved <= 1e-15 * scale) break;
  }
  return std::max({std::abs(r[0]), std::abs(r[1]), std::abs(r[2])});
}
}  // namespace

double step_matrix_limit(StepMatrix step, double w, double c) {
  if (!(w > 0.0) && !(c > 0.0)) return std::numeric_limits<double>::infinity();
  const std::pair<std::complex<double>, std::complex<double>> l = mode_roots(w, c);
  return largest_stable_step(
      [&](double h) {
        double m[9];
        step(h, w, c, m);
        return spectral_radius3(m) <= 1.0 + 1e-9;
      },
      std::max(std::abs(l.first), std::abs(l.second)));
}

std::vector<double> taylor(int order) {
  std::vector<double> a{1.0};
  for (int m = 1; m <= order; ++m) a.push_back(a.back() / m);
  return a;
}

double symplectic_euler_limit(double w, double c) {
  return w > 0.0 ? (std::sqrt(c * c + 4.0 * w * w) - c) / (w * w) : 2.0 / c;
}

double explicit_limit(int order, double w, double c) { return polynomial_limit(taylor(order), w, c); }

double fixed_point_limit(int iterations, double w, double c) {
  return polynomial_limit(std::vector<double>(iterations + 2, 1.0), w, c);
}

}  // namespace clothsim::analysis
