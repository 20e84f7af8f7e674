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
  // The velocity changes of the two steps before that (3 x B each, empty before two and three
  // steps), and the order of the polynomial through the last steps' dv the next step starts
  // from: 0 = dv_n, 1 = the line 2 dv_n - dv_{n-1}, 2 = the parabola 3 dv_n - 3 dv_{n-1} +
  // dv_{n-2}; chosen by which of them the last step's solution lay closest to.
  Eigen::Matrix3Xd implicit_dv_before, implicit_dv_before2;
  int implicit_guess_order = 0;
  std::vector<std::int32_t> implicit_held;
  // The linearisation of the Newton matrix implicit_euler last assembled (sparse_system.h),
  // which later iterations and steps reuse while the residual shows it still serves: the
  // end-of-step positions (3 x B), the spring lengths at that step's start (S), the inverse
  // masses (B) and the step size it was assembled with. The matrix is scratch (in the
  // Workspace) and a function of these: a Workspace that does not hold it (a fresh one, or one
  // that last served another State) rebuilds it from them, bit for bit. implicit_lin_id names
  // the assembly (unique in the process, 0 = none), so a Workspace holding it knows it does.
  Eigen::Matrix3Xd implicit_lin_y;
  std::vector<double> implicit_lin_length;
  Eigen::VectorXd implicit_lin_inv_mass;
  double implicit_lin_h = 0.0;
  std::uint64_t implicit_lin_id = 0;
  // Whether the last step that tried that matrix on a new iterate converged with it (or
  // contracted its residual enough); if not, steps assemble afresh and try it again only every
  // 16th step.
  bool implicit_lin_trusted = true;
  // Whether the last step's linear solves needed the sparse factor
  // (cholesky_preconditioner.h), so that the next factors at its first solve.
  bool implicit_factored = false;
};

// The state at t = 0, with the actions scheduled at t = 0 applied.
State initial_state(const Model& model);

}  // namespace clothsim
