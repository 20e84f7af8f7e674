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
  Eigen::Matrix3Xd gradient;                           // (3 x B) grad_y G: residuals, contact impulses
  std::vector<HeldContact> held;                       // PD's and VBD's contacts on their planes at the step's end
  std::vector<double> lambda;  // XPBD's multipliers (S), PD's contact forces (P)
  PdSystem pd_system;                                  // PD's right-hand side and solve
  PdFactor pd;
  VbdGraph vbd;
  VbdGrid vbd_grid;                                    // VBD's colour-major grid
  std::vector<VbdContact> vbd_contacts;                // (P) VBD's contacts on the spring graph
  XpbdFamilies xpbd;                                    // XPBD's sets and SoA iterate
};

SolverCache& solver_cache(Workspace& ws);


// What a solver's stop measures (docs/integrators.md, "Stopping on a residual"): G's residual
// (step_residual; projective dynamics and VBD, whose converged step minimises G), or, for XPBD,
// whose fixed point is its own (the damper's form, the order of its projections), the change
// of the iterate over an iteration, |y_k - y_{k-1}| relative to the first iteration's.
enum class ResidualForm { StepPotential, IterateChange };

// A step's stop on the residual: with a tolerance, the residual relative to the first
// guess's (IterateChange: to the first iteration's change), checked after each iteration;
// without, nothing is measured.
class ResidualStop {
 public:
  // Measures the first guess y0 when there is a tolerance.
  ResidualStop(const Model& model, const StepProblem& p, ResidualForm form, double tolerance,
               const Eigen::Matrix3Xd& y0, Eigen::Matrix3Xd& scratch);
  bool active() const { return tolerance_ > 0.0; }
  // After an iteration that reached y: whether the step may stop there. `held`: the solver's
  // contacts on their planes at y (step_residual), or null.
  bool met(const Eigen::Matrix3Xd& y, const std::vector<HeldContact>* held = nullptr);
  // The step's verdict: StepStats::residual and converged (true without a tolerance).
  void report(StepStats& stats) const;

 private:
  const Model& model_;
  const StepProblem& p_;
  ResidualForm form_;
  double tolerance_;
  Eigen::Matrix3Xd& scratch_;  // StepPotential: the gradient; IterateChange: the last iterate
  double initial_ = 0.0, relative_ = 0.0;
};

// The largest strain (ln - l0) / l0 of the step's start lengths (StepStats::start_strain).
double max_start_strain(const Model& model, const StepProblem& p);

}  // namespace clothsim
