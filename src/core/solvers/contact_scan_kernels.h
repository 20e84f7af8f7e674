// Which particles lie inside a collider's reach (step_problem.h's test: y below the ground's
// reach, or |y - c| < r + margin for a kinematic sphere), in SIMD, so that the solvers' contact
// passes visit only those instead of every particle every iteration.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "step_problem.h"

namespace clothsim {

// Particles i < n inside some collider's reach, ascending, into `inside` (cleared first).
// y is structure of arrays: component c of particle i at y[c * stride + i].
void particles_in_reach(const Colliders& c, const double* y, std::size_t stride, std::size_t n,
                        std::vector<std::int32_t>& inside);

// The same for y as 3 x B columns (particles 0 .. n - 1).
void particles_in_reach(const Colliders& c, const Eigen::Matrix3Xd& y, std::size_t n,
                        std::vector<std::int32_t>& inside);

}  // namespace clothsim
