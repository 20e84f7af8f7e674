// State: everything that changes while a scene runs, as flat arrays (MuJoCo's mjData).
// A State is a value: copy it to checkpoint, compare two to measure error.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "model.h"

namespace clothsim {

struct State {
  Eigen::Matrix3Xd x;         // (3 x B) body positions, m (particles, then sphere centres)
  Eigen::Matrix3Xd v;         // (3 x B) body velocities, m/s
  Eigen::VectorXd inv_mass;   // (B) 1/kg; 0 = immovable (pinned particle, kinematic sphere)
  double t = 0.0;             // s
  std::int64_t step = 0;      // steps taken
  std::size_t next_action = 0;  // index into model.timeline of the first action not yet applied
  // implicit_euler's solver state, kept here (not in scratch) so a copied State continues bit
  // for bit: its last step's velocity change, the next step's first guess (3 x B, empty
  // before one), and the particles its contacts held at the end of that step (the active
  // set's first guess).
  Eigen::Matrix3Xd implicit_dv;
  std::vector<std::int32_t> implicit_held;
  // Whether the last step's linear solves needed the sparse factor
  // (cholesky_preconditioner.h), so that the next factors at its first solve.
  bool implicit_factored = false;
};

// The state at t = 0, with the actions scheduled at t = 0 applied.
State initial_state(const Model& model);

}  // namespace clothsim
