// Projective dynamics' local step in SIMD over the grid's stencil families (spring_layout.h),
// walked as the force pass walks them (spring_window-inl.h): contiguous loads of each
// family's ends, the terms summed at a and at b in separate arrays, each particle's sum added
// to its row of the residual when the walk finishes it. A spring's term is the scalar pass's,
// k (p_s - d) = k (rest / l - 1) d, with k = ks + kd/h one value per family.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "core/springs/spring_layout.h"

namespace clothsim {

// z.col(row[i]).head<3>() += sum over the springs at particle i of +-k (p_s - d_s), for every particle
// with row[i] >= 0 (z in the factor's order, padded as the solve reads it); rest: the blended
// rest lengths by slot.
void pd_family_projections(const SpringLayout& layout, const Eigen::Matrix3Xd& y,
                           const double* rest, double h, const std::int32_t* row, Eigen::Matrix4Xd& z);

}  // namespace clothsim
