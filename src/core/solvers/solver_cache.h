// The iterative solvers' scratch, kept in the run's Workspace: sizes, the VBD colouring and
// the projective-dynamics factor (a function of h and the pins, rebuilt when one
// changes). Nothing in it changes a step's result: a fresh cache gives the same bits.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pd_kernels.h"
#include "step_problem.h"
#include "vbd_grid_kernels.h"
#include "vbd_kernels.h"
#include "xpbd_family_kernels.h"
#include "core/base/step_stats.h"
#include "core/base/workspace.h"

namespace clothsim {

struct SolverCache {
  StepProblem problem;
  Eigen::Matrix3Xd y, y_before, y_next, acceleration;  // (3 x B)
  std::vector<double> lambda;  // XPBD's multipliers (S), PD's contact forces (P)
  PdSystem pd_system;                                  // PD's right-hand side and solve
  PdFactor pd;
  VbdGraph vbd;
  VbdGrid vbd_grid;                                    // VBD's colour-major grid
  std::vector<VbdContact> vbd_contacts;                // (P) VBD's contacts on the spring graph
  XpbdFamilies xpbd;                                    // XPBD's sets and SoA iterate
};

SolverCache& solver_cache(Workspace& ws);


// The largest strain (ln - l0) / l0 of the step's start lengths (StepStats::start_strain).
double max_start_strain(const Model& model, const StepProblem& p);

}  // namespace clothsim
