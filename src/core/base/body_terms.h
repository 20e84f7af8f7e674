// The per-body terms a force evaluation ends with, after the spring pass: gravity m g on the
// bodies it acts on, air drag -c v on cloth particles, then, for accelerations, each body's sum
// times its inverse mass; immovable bodies (inverse mass 0: pinned particles, kinematic
// spheres) get exactly 0. The SIMD spring pass applies them as it finishes each particle
// (spring_kernels.h), the same operations in the same order per component, so the bits are
// those of body_terms() below, which does the rest (bodies no spring reaches, spheres, layouts
// the kernel does not cover).
#pragma once

#include <cstddef>
#include <cstdint>

namespace clothsim {

struct BodyTermInputs {
  const double* mass = nullptr;              // (B) kg
  const double* inv_mass = nullptr;          // (B) 1/kg, 0 where immovable
  const std::uint8_t* gravity_on = nullptr;  // (B) 1 where gravity acts
  const double* v = nullptr;                 // (3 x B) m/s, for drag
  std::size_t bodies = 0;                    // B
  std::size_t particles = 0;                 // P <= B: bodies [0, P) are cloth particles (drag acts)
  double drag = 0.0;                         // c, N s/m per particle
  double g[3] = {0.0, 0.0, 0.0};             // m/s^2
  bool times_inverse_mass = false;           // accelerations: f / m
};

// Body i's terms on its force fi (three doubles): ((f + m g) - c v) / m, or 0 if immovable.
inline void body_terms(const BodyTermInputs& in, std::size_t i, double* fi) {
  const double w = in.inv_mass[i];
  // In registers, stored once: storing each step and reloading stalls on store forwarding.
  double fx = 0.0, fy = 0.0, fz = 0.0;  // pinned particle or kinematic sphere: filtered
  if (w != 0.0) {
    fx = fi[0], fy = fi[1], fz = fi[2];
    if (in.gravity_on[i]) {
      const double m = in.mass[i];
      fx += m * in.g[0], fy += m * in.g[1], fz += m * in.g[2];
    }
    if (i < in.particles && in.drag != 0.0) {  // air acts on cloth
      const double* vi = in.v + 3 * i;
      fx -= in.drag * vi[0], fy -= in.drag * vi[1], fz -= in.drag * vi[2];
    }
    if (in.times_inverse_mass) fx *= w, fy *= w, fz *= w;
  }
  fi[0] = fx, fi[1] = fy, fi[2] = fz;
}

}  // namespace clothsim
