// The Newton iterations of one backward Euler step (implicit_euler.cpp states the equation and
// the method; docs/implicit_euler.md explains the constants in newton_solve.cpp).
//
// NewtonSolve keeps three small records of its course, each with named transitions:
//   MatrixReuse   whether a direction may use the Newton matrix in hand instead of assembling
//                 one, and the verdict on a direction that did (judged at the next residual);
//   FactorAccount block-Jacobi and factored PCG work this step, which decides when a sparse
//                 factor pays for itself (rent against buy);
//   ContactScan   which iterate and held set the last take-in scan saw, so it is not repeated.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>

#include "implicit_cache.h"
#include "step_potential.h"
#include "core/base/step_stats.h"
#include "core/base/workspace.h"

namespace clothsim {

// Formats the trace's lines for Workspace::newton_trace (nothing when it is empty).
class NewtonTracer {
 public:
  explicit NewtonTracer(const Workspace& ws)
      : sink_(ws.newton_trace ? &ws.newton_trace : nullptr), ws_(&ws) {}
  bool on() const { return sink_ != nullptr; }
  // The run asks the step to end (Workspace::interrupt): the solve stops at its next iteration.
  bool stop_requested() const { return ws_->interrupted(); }
  [[gnu::format(printf, 2, 3)]] void operator()(const char* format, ...) const;

 private:
  const std::function<void(const char*)>* sink_;
  const Workspace* ws_;
};

// Whether the next Newton direction may be taken with the matrix in hand (the recorded one, or
// one assembled earlier this step) and, once one was, whether it served.
struct MatrixReuse {
  enum class Phase {
    Barred,   // every direction assembles at its iterate
    Allowed,  // a direction may use the matrix in hand
    OnTrial,  // the last direction used it: the next residual judges it
  };
  Phase phase = Phase::Barred;
  bool trusted = true;        // the recorded matrix served when last judged (State's lin_trusted)
  double reach = 0.0;         // m, how far from its linearisation point the matrix may serve
  double trial_from = 0.0;    // |S r| before the direction on trial
  bool trial_clean = false;   // that direction's CG converged and its full step was taken
  int unserved = 0;           // directions on trial that did not serve (not charged to the budget)

  bool allowed() const { return phase != Phase::Barred; }
  void start_trial(double r_norm) {
    phase = Phase::OnTrial;
    trial_from = r_norm;
  }
  // The direction on trial served if the residual met the tolerance or contracted enough.
  void judge(bool served) {
    phase = served ? Phase::Allowed : Phase::Barred;
    trusted = served;
    unserved += !served;
  }
  // A direction on trial gave no descent or no step: not a verdict on the iterate.
  void fail() { judge(false); }
};

// Rent against buy, in block-Jacobi PCG iterations (one block mat-vec and one block-diagonal
// solve each): a new factor pays where the work it saves over the solves left in its life (the
// rest of the step: a factor serves one step) exceeds its price. The inputs are forecasts
// from this step's solves (FactorAccount); the rule is the comparison alone.
struct FactorForecast {
  double price = 0.0;        // one numeric factorization
  double now = 0.0;          // the solve in hand's work still to do without the new factor
  double per_solve = 0.0;    // a later solve's work without it (block Jacobi, or the stale factor)
  double fresh = 0.0;        // a solve's work with a fresh factor, its applications included
  double solves_left = 0.0;  // later solves in the factor's life
};
bool factor_pays(const FactorForecast& f);

// Block-Jacobi against sparse-factor PCG work this step, in block-Jacobi iterations, and the
// forecasts built from it.
struct FactorAccount {
  bool first = false;         // the last step's factor paid: build one at the first solve
  bool built = false;         // this step built a factor
  int solves = 0;             // PCG solves this step
  int jacobi_solves = 0;      // of them with block Jacobi
  int factored_solves = 0;    // of them with the factor in hand, since it was built
  double jacobi_work = 0.0;   // block-Jacobi PCG iterations this step
  double factor_work = 0.0;   // the same units spent with the factor since it was built
  double last = 0.0;          // the last factored solve's work
  double jacobi_forecast = 0.0;  // a block-Jacobi solve's work: when the factor was built, or
                                 // carried from the step that measured it (State)

  // Records a solve of `iterations`, each costing `unit` (1 + the factor's solve cost, or 1).
  void record(int iterations, bool factored, double unit);
  // A block-Jacobi solve of `iterations` stopped above tolerance at `relative` (|r| / |b|) where
  // it needed `target`: the iterations still to go, from its rate so far (at most `left`).
  static double remaining(int iterations, double relative, double target, double left);
  // At a block-Jacobi solve stopped at the rent's cap: whether to buy (`rest`: its remaining
  // iterations; `fresh`: a fresh factor's solve, forecast). Later solves: as many again as the
  // step has had, each at block Jacobi's mean (the current one's forecast included).
  FactorForecast buy(double price, double rest, double fresh) const;
  // At a solve's start with the factor in hand: whether a new one would pay.
  FactorForecast renew(double price) const;
  // Block Jacobi's solves this step on average, else the forecast carried in.
  double jacobi_mean() const { return jacobi_solves > 0 ? jacobi_work / jacobi_solves : jacobi_forecast; }
  // The factor's solves so far, on average (0: none yet).
  double mean() const { return factored_solves > 0 ? factor_work / factored_solves : 0.0; }
  // Whether the factor in hand has cost more a solve than block Jacobi did (drop it).
  bool losing() const { return factored_solves >= 2 && jacobi_forecast > 0.0 && mean() > jacobi_forecast; }
  // Whether the factor this step paid: its solves cheaper than block Jacobi's forecast (or no
  // block-Jacobi solve to compare with: built at the step's start, as the last one paid).
  bool paid() const { return built && (jacobi_forecast == 0.0 || mean() < jacobi_forecast); }
};

// The V-cycle's hierarchy against the matrix in hand: built at the step's first direction and
// kept while it serves (any SPD preconditioner gives a correct solve; a stale one only costs
// iterations), rebuilt at a new matrix once a solve with it took more than twice the
// iterations of the first solve after its build, or at once where the held set changed (the Galerkin products cost about as much as
// a few cycles, BENCHMARKS.md #37).
struct MultigridAccount {
  int fresh = -1;        // PCG iterations of the first solve after the build (-1: none yet)
  int last = 0;          // of the last solve
  bool outdated = false; // the matrix changed since the build
  std::uint64_t held_version = 0;  // ContactScan's held set it was built with
  // A new held set always (the smoother would move bodies along normals now held).
  bool rebuild(std::uint64_t held) const { return held != held_version || (outdated && last > 2 * fresh + 2); }
};

// Whether the solve still makes progress: a step is NOT CONVERGED when it stalls, not when it
// has taken some number of iterations. Progress is the residual halving from its best at the
// last mark, or Phi falling by a meaningful fraction of its size since then (a globalised
// Newton crawling through a buckled state lowers Phi while its residual wanders).
struct StallWatch {
  double best = std::numeric_limits<double>::infinity();     // residual at the last mark
  double phi = std::numeric_limits<double>::infinity();      // J, Phi at the last mark
  int mark = 0;                                              // Newton iteration of the last mark
  // Called at each iterate; true once `window` iterations passed without progress.
  bool stalled(int iteration, double residual, const PotentialValue& at, int window);
};

// The inputs of the last take-in scan, counted: y_version changes with the iterate,
// held_version with the held set.
struct ContactScan {
  std::uint64_t y_version = 0, held_version = 0;
  std::uint64_t scanned_y = ~std::uint64_t{0}, scanned_held = ~std::uint64_t{0};
  bool fresh() const { return scanned_y != y_version || scanned_held != held_version; }
  void mark() {
    scanned_y = y_version;
    scanned_held = held_version;
  }
};

// The trust region of the Newton directions (from ImplicitDef::trust_region_from particles),
// in CG's preconditioner's norm |d|_P = sqrt(d^T P d) (P the matrix the preconditioner
// inverts: the mass-dominated diagonal blocks for block Jacobi; the mass norm measured worse,
// BENCHMARKS.md #37, round s34): unbounded at a step's start (a sheet that the quadratic model
// describes takes full Newton steps as before), then updated by rho, Phi's actual decrease
// over the model's at the direction's first trial (Nocedal & Wright, Algorithm 4.1). A trial
// that is not accepted is backtracked rather than solved again (Nocedal & Yuan 1998): one CG
// solve per iteration.
struct TrustRadius {
  double radius = std::numeric_limits<double>::infinity();  // sqrt(J): |d|_P's unit
  // rho < 1/4: a quarter of the step tried, or the step the line search took if shorter;
  // rho > 3/4 at the boundary: doubled.
  void update(double rho, double tried, double taken, bool at_boundary) {
    if (!(rho >= 0.25)) radius = std::min(0.25 * tried, taken);  // (NaN, -inf: Phi not finite)
    else if (rho > 0.75 && at_boundary) radius = 2.0 * radius;
  }
};

// Scales each of the first P columns of d longer than `cap` down to that length; returns how
// many it scaled. A per-particle bound on a Newton direction: at the buckled rim a few dozen
// particles' share of a direction runs to a spring length or more while the rest of the sheet's
// is a hundredth of one, and a single trust radius (or line-search step) for the whole sheet
// would shrink everybody's step for those few (BENCHMARKS.md #37, round s35).
int cap_particle_steps(Eigen::Matrix3Xd& d, Eigen::Index P, double cap);
// How many of the first P columns of d are longer than `cap` (what cap_particle_steps would
// scale), leaving d as it is.
int particle_steps_over(const Eigen::Matrix3Xd& d, Eigen::Index P, double cap);

class NewtonSolve {
 public:
  // `start` is read as the step's start throughout; only its record of the Newton matrix's
  // linearisation (State::implicit.lin) is written, when a matrix is assembled.
  // `form`: the step's incremental potential (step_form.h; a bare h: backward Euler's);
  // `cfg`: the run's Newton and CG settings (MethodSettings::implicit), outliving the solve.
  NewtonSolve(const Model& model, const ImplicitDef& cfg, State& start, const StepForm& form, ImplicitCache& c,
              StepStats& stats, const NewtonTracer& trace);

  void evaluate();           // Phi, r and y at c.dv
  bool update_contacts();    // let go of pulling contacts, then take in; whether the set changed
  void set_scale(double impulse_scale) { impulse_scale_ = impulse_scale; }
  // Newton iterations from the iterate in c until the filtered residual is below tolerance
  // or the step's budget is spent; warm: a CG start for the first direction, or null.
  // Returns whether it converged.
  bool iterate(const Eigen::Matrix3Xd* warm);
  bool factored() const { return account_.paid(); }  // the next step starts with a factor
  double jacobi_solve() const { return account_.jacobi_mean(); }  // State's jacobi_solve
  bool trusted() const { return reuse_.trusted; }

 private:
  struct Residual {
    double norm;   // N s, |S r|
    double scale;  // N s, what it is measured against: max(|h f| at the start, |M dv|)
  };
  Residual measure_residual();  // at the iterate; sets rhs and stats.residual, judges a trial
  bool out_of_budget() const;
  CgSettings cg_settings(double r_norm, double scale) const;
  bool take_step(double slope, bool reused);
  bool take_in();
  double direction(CgSettings settings, const Eigen::Matrix3Xd* warm, bool reused);
  bool may_reuse() const;
  void prepare_matrix(bool reused);
  void record_linearisation();
  void choose_preconditioner();
  bool prepare_multigrid();
  bool near_linearisation() const;
  CgResult solve(const CgSettings& settings);
  bool factorize();
  double fresh_solve() const;
  bool line_search(double slope);
  double cap_direction(double slope);
  void update_trust(double slope);
  double barrier_bound() const;

  const Model& model_;
  const State& start_;
  State& record_;  // the same State: its implicit.lin only
  const StepForm form_;
  const double h_;  // form_.h
  const ImplicitDef& cfg_;
  ImplicitCache& c_;
  StepStats& stats_;
  const NewtonTracer& trace_;
  PotentialValue phi_;
  double impulse_scale_ = 0.0;
  const bool single_step_;  // NewtonMode::BaraffWitkin: one linearised step, taken whole
  const PreconditionerKind preconditioner_;  // resolved: never Auto
  const bool trust_on_;  // the trust region and sqrt forcing (ImplicitDef::trust_region_from)
  MatrixReuse reuse_;
  FactorAccount account_;
  MultigridAccount multigrid_;
  ContactScan scan_;
  StallWatch stall_;
  double alpha_ = 0.0;    // the last line search's step
  double r_norm2_ = 0.0;  // |S r|^2 at the iterate
  TrustRadius trust_;
  bool boundary_ = false;     // the last direction ended on the trust radius
  double step_norm_ = 0.0;    // its length in the region's norm (0: no region applied)
  double model_value_ = 0.0;  // J, CG's model q(d) = d.A d / 2 - rhs.d at it
  bool capped_ = false;       // the last direction was capped per particle (cap_direction)
  double capped_curvature_ = 0.0;  // d.A d of the capped direction
  double first_alpha_ = 0.0;  // the last line search's first trial step
  double first_drop_ = 0.0;   // J, Phi's decrease at that trial (NaN: below rounding)
};

// implicit.preconditioner `asked` on a sheet of `particles`: auto resolved by the sheet's size
// (the solve's, and the memory estimate's before a Model exists).
PreconditionerKind resolved_preconditioner(PreconditionerKind asked, double particles);

// MatrixReuse::reach for springs as short as `shortest` and as stiff as `stiffness`.
double reuse_reach(double shortest, const analysis::StiffnessEstimate& stiffness, double h);

}  // namespace clothsim
