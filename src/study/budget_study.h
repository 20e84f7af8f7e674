// Substeps against iterations at equal cost (`clothsim bench --budget N`, issue #49 item 3).
//
// An engineer with a frame to fill and a solver to run chooses how to spend N iterations a frame:
// s substeps of k iterations each, s x k = N. Macklin et al. 2019 ("Small Steps in Physics
// Simulation", Fig. 1) say the small steps win: 1 substep x 30 XPBD iterations stretches visibly,
// 30 substeps x 1 iteration does not, at about equal cost. This study lays out the whole grid: for
// each iterative solver (xpbd, vbd, projective_dynamics; implicit_euler with Newton capped at k),
// every divisor pair s x k = N, each run at step 1 / (F s) with k iterations a step over T, its
// state compared with the reference at every frame.
//
// The reference is compare's (reference.h): on a smooth scene the adaptive Dormand-Prince pair at
// `reference_tolerance` (served) and 10x tighter (its check), twice their largest distance over
// the frames its estimated error; otherwise RK4 at `reference_dt` (the plan's: compare's rule, a quarter of the smallest
// step, cut to RK4's predicted stable step) checked by RK4 at twice that step. Both solves run
// first, on two threads, keeping the served one's positions at every frame (3 x P doubles a
// frame); then the grid's runs spread over the task pool, each measured frame by frame against
// those positions, so no run keeps more than its own state.
//
// Per point: the largest particle distance from the reference over the frames (L-infinity in
// time, and the frame it is reached at), the largest spring strain over the run (every step's
// start and the last state), the energy lost per second ((E(0) - E(T)) / T: a solver's own
// dissipation where colliders are static; where a collider moves, its work is in the figure, the
// same for every run, so compare with the reference's), and the CPU time of the run's thread.
// A run that diverges, reads WRONG, or whose error is under 1 / reference_margin times the
// reference's own (unresolved) is marked as bench marks them.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "reference.h"
#include "study.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/diagnostics.h"
#include "core/model/model.h"
#include "core/run/simulation.h"

namespace clothsim::analysis {

struct BudgetSpec {
  int budget = 30;          // N: iterations a frame, s x k
  double fps = 60.0;        // F: frames per simulated second (the frame the budget fills)
  double duration = 0.0;    // T, s: a whole number of frames (T F within 1e-9 of an integer)
  std::vector<IntegratorKind> solvers;     // each iterative (IterationControl not None)
  std::vector<std::string> solver_names;   // per solver, as rows say it ("xpbd"); empty: the integrator's
  // The settings solver i runs with at k iterations a step, on the study's model (the plan's: the
  // lane `NAME:k` through clip::lane_settings); null: the model's with the solver's iteration
  // count (iteration_count) set to k.
  std::function<MethodSettings(const Model& base, std::size_t solver, int k)> solver_settings;
  double reference_tolerance = kReferenceTolerance;  // a smooth scene: the served solve's (its check 10x tighter)
  double reference_dt = 0.0;          // otherwise: RK4's step, s (> 0, at most the smallest step)
  double reference_margin = 0.1;      // unresolved: error x margin under the reference's own
  int jobs = 0;                       // threads; <= 0: hardware_concurrency
};

// The divisors of n, ascending: the substep counts of the grid (n = 30: 1 2 3 5 6 10 15 30).
std::vector<int> divisors(int n);

struct BudgetPoint {
  std::size_t solver = 0;      // index into spec.solvers
  IntegratorKind kind{};
  int substeps = 0;            // s, steps a frame
  int iterations = 0;          // k, iterations a step (implicit_euler: its Newton cap)
  double dt = 0.0;             // s, 1 / (F s)
  bool finished = false;       // reached T
  bool diverged = false;
  double diverged_at = 0.0;    // s
  std::string reason;          // why it diverged
  RunTotals totals;            // steps, evaluations, iterations, CPU; totals.wrong: WRONG's first verdict
  int frames = 0;              // frames measured against the reference
  double max_error = 0.0;      // m, largest particle distance over the frames; NaN unless finished
  double max_error_t = 0.0;    // s, the frame it is reached at
  double final_error = 0.0;    // m, the same at T; NaN unless finished
  double max_strain = 0.0;     // largest (l - l0) / l0 over the run
  double energy_lost_per_second = 0.0;  // J/s, (E(0) - E(T)) / T; NaN unless finished
  bool unresolved = false;     // finished, error under 1 / margin x the reference's estimated error
  bool wrong() const { return totals.wrong.has_value(); }
};

struct BudgetReference {
  bool adaptive = false;         // the adaptive pair (tolerance), else RK4 (dt)
  double tolerance = 0.0;        // the served solve's; the check's is kCheckTightening tighter
  double dt = 0.0;               // s, RK4's step (its check at 2 dt)
  bool finished = false;         // both solves reached T
  std::string failure;           // why not (a divergence or a stop), "" when finished
  double estimated_error = 0.0;  // m, largest distance between the two solves over the frames
                                 // (NaN when the check alone failed: no estimate)
  double max_strain = 0.0;       // the served solve's largest strain at the frames
  double energy_lost_per_second = 0.0;  // J/s, the served solve's (E(0) - E(T)) / T
  double cpu_seconds = 0.0;      // both solves
  std::int64_t steps = 0, force_evals = 0;
};

struct BudgetResult {
  BudgetSpec spec;               // checked: what ran
  int frames = 0;                // T F
  bool colliders_move = false;   // a kinematic sphere moves within T: energy lost includes its work
  BudgetReference reference;
  std::vector<BudgetPoint> points;  // solver by solver, substeps ascending (those that ran)
  bool complete = true;          // false when stopped early
};

// The grid in the order it is reported: per solver, s ascending, k = N / s; not yet run.
std::vector<BudgetPoint> budget_points(const BudgetSpec& spec);

// Checks the spec (throws StudyError naming the problem: a budget under 1 or over
// kMaxSolverIterations, a solver without iterations, F or T not positive, T not a whole number of
// frames, a reference step that is missing or over the smallest step); returns it unchanged.
BudgetSpec checked(BudgetSpec spec);

// The reference, then every point of the grid, over the task pool.
BudgetResult budget_study(const Model& model, const BudgetSpec& spec, const StudyHooks& hooks = {});

// Solver i's name (spec.solver_names, else the integrator's).
std::string solver_name(const BudgetSpec& spec, std::size_t i);

// The status bench prints: "DIVERGED at t = 0.2 s: ...", "NOT CONVERGED: ...", "WRONG at ...",
// "unresolved: ...", "ok (Newton capped at 3: residual up to 0.01)" or "ok".
std::string budget_status(const BudgetPoint& p, double margin);

// The split that wins solver i's grid: the least error among the runs that finished and are not
// WRONG (an unresolved one is below every resolved one, the cheapest unresolved first); -1 when
// none did, or when every one is unresolved (the reference cannot rank them: the text says so,
// with the two ends' strains). `against`: the grid's end it is set beside (1 x N, or N x 1 when
// 1 x N wins); an inner winner is set beside both ends' errors.
struct BudgetVerdict {
  int winner = -1, against = -1;  // indices into result.points
  std::string text;  // "xpbd at N = 30: 30 substeps x 1 iteration wins: error 3.1 mm against 41 mm
                     //  for 1 x 30, strain 0.004 against 0.09, CPU 1.1x"
};
BudgetVerdict budget_verdict(const BudgetResult& r, std::size_t solver);

}  // namespace clothsim::analysis
