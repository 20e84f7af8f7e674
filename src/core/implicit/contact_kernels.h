// The contact search's first test in SIMD (step_contacts.cpp's NearColliders): which particles'
// end positions lie below the ground's bound or inside a kinematic sphere's widened reach, N
// particles at a time, through Google Highway with runtime dispatch. The test only screens:
// every particle it flags still goes through the exact search, and the bounds are widened far
// beyond the rounding of the squares, so the contacts found do not depend on it (nor on the
// target: Mul and Add, no fused multiply-add).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace clothsim {

struct NearScreen {
  const double* centre = nullptr;  // (3 x S) the spheres' end-of-step centres
  const double* bound2 = nullptr;  // (S) squared widened reach
  std::size_t spheres = 0;         // S
  double ground = 0.0;             // flagged below this height (-inf: no ground)
};

// The particles p < n, in order, whose end position (x + h (v + g), or x + h v without g, or x
// without v; each 3 x n) may be within a collider's bound, into `near` (cleared first).
void near_screen(const NearScreen& screen, const double* x, const double* v, const double* g,
                 double h, std::size_t n, std::vector<std::int32_t>& near);

}  // namespace clothsim
