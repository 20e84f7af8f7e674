// implicit_euler's scratch: the sparse pattern and the buffers its Newton solve needs, built
// once per model (a Workspace belongs to one run, so to one model). Nothing here carries from
// one step to the next but what State's record names (ImplicitSolverState::lin).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sparse_system.h"
#include "step_contacts.h"
#include "core/base/step_stats.h"
#include "core/base/workspace.h"
#include "core/linear/cg_kernels.h"
#include "core/linear/cholesky_preconditioner.h"
#include "core/linear/conjugate_gradient.h"
#include "core/linear/multigrid_preconditioner.h"
#include "core/model/model.h"
#include "core/model/state.h"
#include "core/model/stiffness_estimate.h"

namespace clothsim {

struct ImplicitCache {
  const Model* model = nullptr;
  int single_from = 0;         // the ImplicitDef::single_from A was built with
  double force_scale = 0.0;    // N, sqrt(sum_s (ks_s l0_s)^2): the size of the spring forces' terms
  double shortest_rest = 0.0;  // m, the shortest rest length (infinite without springs)
  analysis::StiffnessEstimate stiffness;  // Gershgorin bounds the matrix-reuse distance uses
  SpringBlockMatrix A;                    // the Newton matrix
  // imex's damping matrix M - h/2 D (integrators/imex.cpp), its pattern built on first use, and
  // the mark of the assembly it holds (0: none), which the State's history names when its end
  // state is where it was assembled.
  SpringBlockMatrix damping;
  std::uint64_t damping_mark = 0;
  std::vector<double> start_length;       // (slots) m, l_n (step_lengths)
  // (slots) m, the springs' lengths at y and at y_try, swapped with them; empty where the
  // springs are not all in families. A step that starts where the last ended reuses y_length.
  std::vector<double> y_length, y_try_length;
  StepContacts contacts;
  Eigen::Matrix3Xd dv, y, r;              // (3 x B) the iterate (m/s), its end positions (m), residual (N s)
  Eigen::Matrix3Xd dv_try, y_try, r_try;  // (3 x B) a line-search trial
  Eigen::Matrix3Xd d, rhs;                // (3 x B) the Newton direction and -S r
  Eigen::Matrix3Xd guess;                 // (3 x B) an extrapolated first guess (guess_through)
  // 1 / w, 1 / w^2 (0 on immovable bodies) for the inverse masses in mass_of, formed again
  // only when a step's inverse masses differ (a pin or unpin).
  Eigen::VectorXd mass, mass_squared, mass_of;  // (B) kg, kg^2, 1/kg
  // The record A was assembled at, when A holds a recorded matrix: a State whose record
  // matches it bit for bit finds its matrix here; any other rebuilds it from its record.
  bool holds_record = false;
  ImplicitSolverState::Linearisation record;
  bool jacobi_ready = false;      // A's block-Jacobi inverse is formed
  CgBuffers cg;
  CholeskyPreconditioner factor;  // built and used within one step
  MultigridPreconditioner multigrid;  // built from each assembled matrix, within one step

  // Whether A is the matrix of `lin` (the assembly count aside).
  bool holds(const ImplicitSolverState::Linearisation& lin) const;
};

// The Workspace's cache, (re)built for `model` and the run's settings `cfg` where it was built
// for another.
ImplicitCache& cache_for(const Model& model, const ImplicitDef& cfg, Workspace& ws);

}  // namespace clothsim
