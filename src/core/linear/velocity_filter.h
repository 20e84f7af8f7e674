// Baraff & Witkin's filter S (1998, "Large Steps in Cloth Simulation", section 5.3): a body
// in contact may not move along its contact normal n during the solve, so every vector the
// solver builds is projected with S_i = I - n n^T on that body. With the start point on the
// constraint plane and every direction filtered, each iterate stays on it: the contact is
// held inside the linear systems, not snapped out after them. (Pinned bodies need no entry:
// the system leaves them out by its identity rows; see sparse_system.h.)
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/springs/spring_force.h"  // Vec3

namespace clothsim {

struct VelocityFilter {
  std::vector<std::int32_t> body;  // (C) constrained bodies, each at most once
  std::vector<Vec3> normal;        // (C) their unit contact normals

  std::size_t size() const { return body.size(); }
  void clear() {
    body.clear();
    normal.clear();
  }
  // v (3 x B) <- S v: removes each constrained body's component along its normal.
  void apply(Eigen::Matrix3Xd& v) const {
    for (std::size_t c = 0; c < body.size(); ++c) {
      auto col = v.col(body[c]);
      col -= normal[c] * normal[c].dot(col);
    }
  }
};

}  // namespace clothsim
