#include "newton_solve.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "barrier_terms.h"
#include "newton_kernels.h"
#include "core/model/barrier_contacts.h"
#include "core/linear/cg_kernels.h"
#include "step_contacts.h"

namespace clothsim {

namespace {

// docs/implicit_euler.md, "Newton's constants", says why each has its value.
constexpr double kArmijo = 1e-4;          // Armijo's sufficient decrease
constexpr int kMaxHalvings = 30;          // line-search halvings from the full step
constexpr double kMaxForcing = 0.1;       // the largest CG forcing term (inexact Newton)
constexpr double kFinishMargin = 10.0;    // solve to the absolute tolerance within this many
constexpr double kReleaseResidual = 1e-2;  // let contacts go below this relative residual
constexpr int kRetryJacobi = 16;          // every 16th step starts with block Jacobi again
constexpr double kFreshIterations = 4.0;  // PCG iterations of a solve with a fresh factor, forecast
constexpr double kReuseContraction = 0.25;  // a reused matrix served if |r| fell 4 times
constexpr int kRetryReuse = 16;           // an untrusted recorded matrix is probed every 16th step
constexpr int kReuseReserve = 2;          // exact iterations a trial must leave in the budget
constexpr double kReuseResidual = 1e-4;   // reuse at any distance below this residual...
constexpr double kReuseChange = 0.05;     // ...or where the matrix is this close to exact
constexpr int kStallWindow = 50;          // iterations without progress that make a stall
constexpr double kStallResidual = 0.5;    // progress: the residual halves...
constexpr double kStallPhi = 1e-6;        // ...or Phi falls by this fraction of its size
// implicit.preconditioner: auto takes block Jacobi alone from this many particles, the rent-
// against-buy of block Jacobi and the sparse factor below it: with the factor built only where
// it pays, block Jacobi cost 0.85-0.9x the rent-against-buy on stiff.yaml refined to 32 x 32 and
// about 1x from 64 x 64 and on the refined drape (no factor pays there), where stiff.yaml's own
// 15 x 15 takes 0.67-0.87x with the factor (BENCHMARKS.md, #37, round s34).
constexpr int kJacobiFromParticles = 32 * 32;
// The largest sparse factor built (L's bytes): larger sheets solve with block Jacobi, so a
// run stays within what memory_estimate.h promises.
constexpr std::size_t kMaxFactorBytes = std::size_t{512} << 20;

// |M dv| over movable bodies (mass_squared[i] = 1 / w_i^2, 0 where w_i = 0).
double momentum_norm(const Eigen::VectorXd& mass_squared, const Eigen::Matrix3Xd& dv) {
  return std::sqrt(simd_weighted_norm2(mass_squared.data(), dv.data(), static_cast<std::size_t>(dv.cols())));
}


// Whether the State's record was made for this system: the same step size and the same
// movable bodies (the matrix's rows for immovable ones are removed).
bool record_fits(const Model& model, const State& start, const StepForm& form) {
  const ImplicitSolverState::Linearisation& lin = start.implicit.lin;
  const int B = model.num_bodies();
  return lin.h != 0.0 && lin.h == form.h && lin.damper_h == form.damper_h && lin.drag_h == form.drag_h &&
         lin.y.cols() == B &&
         lin.length.size() == slot_count(model.spring_layout, model.springs.size()) &&
         lin.inv_mass.size() == B && lin.inv_mass == start.inv_mass;
}

}  // namespace

void NewtonTracer::operator()(const char* format, ...) const {
  if (!sink_) return;
  char line[512];
  std::va_list args;
  va_start(args, format);
  std::vsnprintf(line, sizeof line, format, args);
  va_end(args);
  (*sink_)(line);
}

bool StallWatch::stalled(int iteration, double residual, const PotentialValue& at, int window) {
  if (residual <= kStallResidual * best || at.phi < phi - kStallPhi * at.magnitude) {
    best = std::min(best, residual);
    phi = at.phi;
    mark = iteration;
    return false;
  }
  return iteration - mark >= window;
}

PreconditionerKind resolved_preconditioner(PreconditionerKind asked, double particles) {
  if (asked != PreconditionerKind::Auto) return asked;
  return particles >= kJacobiFromParticles ? PreconditionerKind::BlockJacobi : PreconditionerKind::Cholesky;
}

double reuse_reach(double shortest, const analysis::StiffnessEstimate& stiffness, double h) {
  const double springs = h * stiffness.c_max + std::pow(h * stiffness.w_max, 2);
  return springs > 0.0 ? kReuseChange * shortest / (4.0 * springs) : std::numeric_limits<double>::infinity();
}

NewtonSolve::NewtonSolve(const Model& model, const ImplicitDef& cfg, State& start, const StepForm& form,
                         ImplicitCache& c, StepStats& stats, const NewtonTracer& trace)
    : model_(model), start_(start), record_(start), form_(form), h_(form.h), cfg_(cfg), c_(c), stats_(stats),
      trace_(trace), single_step_(cfg_.newton_mode() == NewtonMode::BaraffWitkin),
      preconditioner_(resolved_preconditioner(cfg.preconditioner, model.num_particles)),
      trust_on_(!single_step_ && model.num_particles >= cfg_.trust_region_from) {
  account_.first = start.implicit.factored && start.step % kRetryJacobi != 0;
  account_.jacobi_forecast = start.implicit.jacobi_solve;
  reuse_.trusted = start.implicit.lin_trusted;
  reuse_.reach = reuse_reach(c_.shortest_rest, c_.stiffness, h_);
  // The recorded matrix may serve if it fits and last served, or as a probe every
  // kRetryReuse-th step. Baraff & Witkin's step is linearised at its own start, always.
  const bool allowed = !single_step_ && record_fits(model, start, form_) &&
                       (reuse_.trusted || start.step % kRetryReuse == 0);
  reuse_.phase = allowed ? MatrixReuse::Phase::Allowed : MatrixReuse::Phase::Barred;
  // A factor serves one step: the next builds its own, so a copied State continues bit for bit.
  c_.factor.invalidate();
  c_.multigrid.invalidate();
}

void NewtonSolve::evaluate() {
  phi_ = step_potential(model_, start_, form_, c_.start_length, c_.dv, c_.y, c_.r, &c_.y_length);
  ++stats_.force_evals;
  ++scan_.y_version;
}

// take_in_step_contacts at the iterate, unless the last scan saw this y with this held set
// (it would find nothing new: the scan is a function of the two).
bool NewtonSolve::take_in() {
  if (!scan_.fresh()) return false;
  const bool changed = take_in_step_contacts(model_, start_, h_, c_.y, c_.contacts);
  if (changed) ++scan_.held_version;
  scan_.mark();
  return changed;
}

bool NewtonSolve::update_contacts() {
  const bool let_go = let_go_step_contacts(c_.r, c_.contacts);
  if (let_go) ++scan_.held_version;
  return take_in() || let_go;
}

NewtonSolve::Residual NewtonSolve::measure_residual() {
  c_.rhs = -c_.r;
  c_.contacts.filter.apply(c_.rhs);
  r_norm2_ = matrix_dot(c_.rhs, c_.rhs);  // (the line search's too: rhs stays as it is till then)
  const double r_norm = std::sqrt(r_norm2_);
  const double scale = std::max(impulse_scale_, momentum_norm(c_.mass_squared, c_.dv));
  // (0 / 0 where nothing can move, no spring and no body term: nothing to solve, solved)
  stats_.residual = r_norm == 0.0 ? 0.0 : r_norm / scale;
  if (reuse_.phase == MatrixReuse::Phase::OnTrial)
    reuse_.judge(stats_.residual <= cfg_.newton_tolerance ||
                 (reuse_.trial_clean && r_norm <= kReuseContraction * reuse_.trial_from));
  return {r_norm, scale};
}

// Directions on trial that did not serve are not charged: the step keeps every exact iteration.
bool NewtonSolve::out_of_budget() const {
  return stats_.newton_iterations - reuse_.unserved >= cfg_.newton_max_iterations ||
         !std::isfinite(stats_.residual);
}

// Inexact Newton: CG's relative tolerance is the forcing term |r| / scale (its square root
// with the trust region, on large sheets where CG iterations are the cost: superlinear rather
// than quadratic, Nocedal & Wright 7.1), capped at kMaxForcing; where that would leave the
// next residual within kFinishMargin of the tolerance, the solve goes to the absolute
// tolerance at once. Baraff & Witkin's single step
// is solved to cg_tolerance: a loose one would accept its warm start as the step.
CgSettings NewtonSolve::cg_settings(double r_norm, double scale) const {
  CgSettings settings;
  settings.max_iterations = cfg_.cg_max_iterations;
  const double forcing = std::min(kMaxForcing, trust_on_ ? std::sqrt(stats_.residual) : stats_.residual);
  const bool finish = forcing * stats_.residual < kFinishMargin * cfg_.newton_tolerance;
  settings.tolerance = single_step_ || finish ? cfg_.cg_tolerance : std::max(cfg_.cg_tolerance, forcing);
  settings.absolute_tolerance = 0.1 * cfg_.newton_tolerance * scale;
  settings.b_norm = r_norm;  // |rhs|, which solve_pcg would compute again
  settings.trust_region = trust_on_;  // in the preconditioner's norm
  settings.trust_radius = trust_.radius;
  return settings;
}

bool NewtonSolve::iterate(const Eigen::Matrix3Xd* warm) {
  for (;;) {
    const Residual r = measure_residual();
    trace_("newton step %lld iteration %d residual %.3e held %zu phi %.10e\n",
           static_cast<long long>(start_.step), stats_.newton_iterations, stats_.residual,
           c_.contacts.size(), phi_.phi);
    if (stats_.residual <= cfg_.newton_tolerance) return true;
    // Near a solution the contact impulses mean something: let go of the pulling ones now
    // rather than converge with them held (the solve would crawl through buckled states).
    if (stats_.residual < kReleaseResidual && update_contacts()) {
      place_on_planes(c_.contacts, start_, h_, c_.dv);
      evaluate();
      trace_("  let go / taken in: held %zu\n", c_.contacts.size());
      continue;
    }
    if (out_of_budget() || stall_.stalled(stats_.newton_iterations, stats_.residual, phi_, kStallWindow) ||
        trace_.stop_requested())
      return false;
    const bool reused = may_reuse();
    if (reused) reuse_.start_trial(r.norm);
    const double slope = direction(cg_settings(r.norm, r.scale), warm, reused);
    warm = nullptr;
    ++stats_.newton_iterations;
    if (!take_step(slope, reused)) {
      // With the exact Hessian, no descent or no step ends the solve (a non-finite system, or
      // rounding has the last word); with a reused one, assemble at the iterate and go on.
      if (!reused) return false;
      reuse_.fail();
    }
  }
}

// Moves the iterate along d (whole for Baraff & Witkin, by line search otherwise) and takes
// in the particles the step took inside a collider. False: no descent or no step.
bool NewtonSolve::take_step(double slope, bool reused) {
  if (trust_on_ && cfg_.direction_cap > 0.0) slope = cap_direction(slope);
  if (!(slope < 0.0) || (!single_step_ && !line_search(slope))) return false;
  if (trust_on_) update_trust(slope);
  if (single_step_) {  // Baraff & Witkin: the linearised step, whole (as far as the barrier allows)
    c_.dv += barrier_bound() * c_.d;
    evaluate();
    return true;  // the next round measures the residual, then stops at the budget
  }
  reuse_.trial_clean = reuse_.trial_clean && alpha_ == 1.0;
  trace_("  line search: step %.3g, slope %.3e, reused matrix %d, trust radius %.3e\n", alpha_, slope,
         reused ? 1 : 0, trust_.radius);
  // Letting go waits until the residual is small (iterate); taking in does not.
  if (take_in()) {
    place_on_planes(c_.contacts, start_, h_, c_.dv);
    evaluate();
    trace_("  taken in: held %zu\n", c_.contacts.size());
  }
  return true;
}

// A direction may use the matrix in hand near the solution (kReuseResidual) or near the
// matrix's linearisation point (kReuseChange), while kReuseReserve exact iterations remain.
bool NewtonSolve::may_reuse() const {
  return reuse_.allowed() && (stats_.residual < kReuseResidual || near_linearisation()) &&
         cfg_.newton_max_iterations - (stats_.newton_iterations - reuse_.unserved) > kReuseReserve;
}

// Whether every particle's end position lies within reach of the recorded linearisation point
// (the spheres have no springs: a kinematic one moving on changes nothing in the matrix).
bool NewtonSolve::near_linearisation() const {
  const std::size_t P = static_cast<std::size_t>(model_.num_particles);
  if (P == 0 || reuse_.reach == std::numeric_limits<double>::infinity()) return true;
  const double reach = reuse_.reach;  // (NaN: not near)
  return simd_max_distance2(c_.y.data(), start_.implicit.lin.y.data(), P) <= reach * reach;
}

// The Newton direction d (in c.d) and its slope r . d: truncated PCG on the exact Hessian
// (Baraff & Witkin: the projected one), which stops at negative curvature with a direction
// that is still downhill (Nocedal & Wright, Algorithm 7.1), or with the trust region there
// and at the radius goes to the boundary (Steihaug-Toint, Algorithm 7.2).
double NewtonSolve::direction(CgSettings settings, const Eigen::Matrix3Xd* warm, bool reused) {
  prepare_matrix(reused);
  settings.from_guess = warm != nullptr;
  if (warm && warm != &c_.d) c_.d = *warm;
  if (preconditioner_ != PreconditionerKind::Cholesky) {  // no factor: one preconditioner throughout
    if (preconditioner_ != PreconditionerKind::Multigrid || !prepare_multigrid()) {
      if (!c_.jacobi_ready) invert_diagonal(c_.A);
      c_.jacobi_ready = true;
    }
    solve(settings);
    return -matrix_dot(c_.rhs, c_.d);
  }
  choose_preconditioner();
  const bool affordable = c_.factor.factor_bytes() <= kMaxFactorBytes;
  const double left = c_.factor.factor_cost() - account_.jacobi_work;
  if (c_.factor.ready() || !affordable || left <= 0.0) {
    solve(settings);  // renting is over: choose_preconditioner decided at the solve's start
  } else {
    // Block Jacobi until this step's Jacobi work would pay for a factor; if the solve is not
    // done by then, factor where that pays and go on from where it stopped (a descent
    // direction already). (clamped so that the cast cannot overflow)
    const int cap = static_cast<int>(std::min(std::ceil(left), 1e9));
    const int budget = settings.max_iterations;
    settings.max_iterations = std::min(budget, cap);
    const CgResult cg = solve(settings);
    if (!cg.converged && !cg.negative_curvature && !cg.boundary && cg.iterations >= cap && cap < budget) {
      const double target = std::max(settings.tolerance, settings.absolute_tolerance / settings.b_norm);
      const double rest = FactorAccount::remaining(cg.iterations, cg.relative_residual, target, budget - cap);
      const bool bought = factor_pays(account_.buy(c_.factor.factor_cost(), rest, fresh_solve())) && factorize();
      settings.max_iterations = bought ? cfg_.cg_max_iterations : budget - cap;
      settings.from_guess = true;
      solve(settings);
    }
  }
  return -matrix_dot(c_.rhs, c_.d);  // r . d (d is filtered)
}

// The matrix for this direction: assembled at the iterate, or the matrix in hand (rebuilt from
// State's record where this Workspace holds another).
void NewtonSolve::prepare_matrix(bool reused) {
  if (!reused) {
    assemble_step_hessian(model_, start_.inv_mass, form_, c_.start_length, c_.y,
                          single_step_ ? HessianBlocks::Projected : HessianBlocks::Exact, c_.A,
                          JacobiInverse::Skip);
    if (uses_barrier(model_)) add_barrier_hessian(model_, start_, form_, c_.y, c_.A);
    ++stats_.assemblies;
    c_.jacobi_ready = false;
    multigrid_.outdated = true;
    c_.holds_record = false;
    if (!single_step_) record_linearisation();
  } else if (!c_.holds(start_.implicit.lin)) {
    const ImplicitSolverState::Linearisation& lin = start_.implicit.lin;
    StepForm recorded(lin.h, lin.damper_h, lin.drag_h);
    recorded.lag_x = form_.lag_x;
    assemble_step_hessian(model_, lin.inv_mass, recorded, lin.length, lin.y, HessianBlocks::Exact, c_.A,
                          JacobiInverse::Skip);
    if (uses_barrier(model_)) add_barrier_hessian(model_, start_, recorded, lin.y, c_.A);
    ++stats_.assemblies;
    c_.jacobi_ready = false;
    multigrid_.outdated = true;
    c_.record = lin;
    c_.holds_record = true;
  }
}

// Writes the point the matrix was just assembled at into State, for later iterations and steps.
void NewtonSolve::record_linearisation() {
  ImplicitSolverState::Linearisation& lin = record_.implicit.lin;
  lin.y = c_.y;
  lin.length = c_.start_length;
  lin.inv_mass = start_.inv_mass;
  lin.h = h_;
  lin.damper_h = form_.damper_h;
  lin.drag_h = form_.drag_h;
  ++lin.assemblies;
  c_.record = lin;
  c_.holds_record = true;
}

// Rent against buy at a solve's start: the factor where the last step's paid; past the rent
// (this step's Jacobi work has reached a factor's price), a factor where its forecast saving
// over the rest of the step exceeds its price; a new factor where the one in hand has grown
// stale by more than that (factor_pays); none where the one in hand costs more a solve than
// block Jacobi did (a stale factor at 256 x 256: 30 iterations of 28 Jacobi iterations' cost).
void NewtonSolve::choose_preconditioner() {
  if (!c_.factor.analysed()) c_.factor.analyse(c_.A, kMaxFactorBytes);
  ++account_.solves;
  const double price = c_.factor.factor_cost();
  if (c_.factor.factor_bytes() <= kMaxFactorBytes) {
    if (c_.factor.ready()) {
      if (account_.losing()) c_.factor.invalidate();  // dearer than block Jacobi: rent again
      else if (factor_pays(account_.renew(price))) factorize();
    } else if (account_.first && account_.solves == 1) {
      factorize();
    } else if (account_.jacobi_work >= price && account_.jacobi_solves > 0) {
      const double per_solve = account_.jacobi_mean();
      if (factor_pays({price, per_solve, per_solve, fresh_solve(), account_.solves - 1.0})) factorize();
    }
  }
  if (!c_.factor.ready()) ++account_.jacobi_solves;
  if (!c_.factor.ready() && !c_.jacobi_ready) {
    invert_diagonal(c_.A);
    c_.jacobi_ready = true;
  }
}

// The V-cycle of the matrix in hand (built once per assembly); false: block Jacobi instead (a
// level not SPD, a non-finite matrix).
bool NewtonSolve::prepare_multigrid() {
  MultigridPreconditioner& mg = c_.multigrid;
  if (!mg.analysed()) mg.analyse(c_.A, model_.grid_nx, model_.grid_ny);
  if (!mg.ready() || multigrid_.rebuild(scan_.held_version)) {
    multigrid_ = MultigridAccount{};
    multigrid_.held_version = scan_.held_version;
    if (!mg.build(c_.A, c_.contacts.filter, start_.inv_mass)) return false;
  }
  return true;
}

CgResult NewtonSolve::solve(const CgSettings& settings) {
  const bool factored = c_.factor.ready();
  const Preconditioner* pre = factored ? static_cast<const Preconditioner*>(&c_.factor)
                              : c_.multigrid.ready() ? &c_.multigrid : nullptr;
  const CgResult cg = solve_pcg(c_.A, c_.rhs, c_.d, settings, c_.cg, &c_.contacts.filter, pre);
  reuse_.trial_clean = cg.converged;
  boundary_ = cg.boundary;
  step_norm_ = cg.step_norm;
  model_value_ = cg.model_value;
  trace_("  cg: %d iterations, converged %d, negative curvature %d, relative residual %.2e, factored %d, "
         "boundary %d\n",
         cg.iterations, cg.converged ? 1 : 0, cg.negative_curvature ? 1 : 0, cg.relative_residual,
         factored ? 1 : 0, cg.boundary ? 1 : 0);
  stats_.cg_iterations += cg.iterations;
  if (c_.multigrid.ready() && !factored) {
    if (multigrid_.fresh < 0) multigrid_.fresh = cg.iterations;
    multigrid_.last = cg.iterations;
  }
  if (factored) stats_.factored_cg_iterations += cg.iterations;
  account_.record(cg.iterations, factored, factored ? 1.0 + c_.factor.solve_cost() : 1.0);
  return cg;
}

// A new factor, its account started; the forecast a block-Jacobi solve's work it was bought
// against is kept, to judge at the step's end whether it paid.
bool NewtonSolve::factorize() {
  account_.jacobi_forecast = account_.jacobi_mean();  // this step's, else the one carried in
  account_.built = true;
  account_.factor_work = 0.0;
  account_.factored_solves = 0;
  ++stats_.factorizations;
  return c_.factor.factorize(c_.A, c_.contacts.filter);
}

// A solve's work with a fresh factor, forecast: kFreshIterations PCG iterations, each a block
// mat-vec and a factored solve.
double NewtonSolve::fresh_solve() const {
  if (account_.factored_solves > 0) return account_.mean();  // observed this step
  return kFreshIterations * (1.0 + c_.factor.solve_cost());
}

bool factor_pays(const FactorForecast& f) {
  const double saving = (f.now - f.fresh) + f.solves_left * (f.per_solve - f.fresh);
  return saving > f.price;
}

void FactorAccount::record(int iterations, bool factored, double unit) {
  if (!factored) {
    jacobi_work += iterations;
    return;
  }
  last = iterations * unit;
  factor_work += last;
  ++factored_solves;
}

// CG's residual falls about geometrically: at rate relative^(1 / iterations) per iteration, the
// target is log(target / relative) / log(rate) iterations away.
double FactorAccount::remaining(int iterations, double relative, double target, double left) {
  if (!(relative > target)) return 0.0;
  if (!(relative < 1.0) || iterations <= 0) return left;
  return std::min(left, iterations * std::log(target / relative) / std::log(relative));
}

// The later solves are forecast as many again as this step has had (the step's solve count
// doubles, as a ski rental's horizon is guessed), each costing block Jacobi's mean so far.
FactorForecast FactorAccount::buy(double price, double rest, double fresh) const {
  const double per_solve = jacobi_solves > 0 ? (jacobi_work + rest) / jacobi_solves : rest;
  return {price, rest, per_solve, fresh, static_cast<double>(solves)};
}

// Over as many solves as the factor in hand has served, a new one would cost what this one
// did (its first solve, on its own matrix, and the staler ones after), and this one at least
// its last solve each (it only grows staler): k solves, k (last - mean) saved.
FactorForecast FactorAccount::renew(double price) const {
  return {price, last, last, factored_solves > 0 ? mean() : last, std::max(0.0, factored_solves - 1.0)};
}

// The largest step along d that keeps every barrier distance positive (1 without the barrier).
double NewtonSolve::barrier_bound() const {
  return uses_barrier(model_) ? barrier_line_bound(model_, start_, form_, c_.y, c_.d) : 1.0;
}

// Armijo backtracking along d from dv, from the barrier's bound; on success the trial becomes
// the iterate. Where Phi's decrease is below its rounding (its terms dwarf their changes), the
// filtered residual decides.
bool NewtonSolve::line_search(double slope) {
  double alpha = barrier_bound();
  alpha_ = 0.0;
  const double resolvable = 64.0 * std::numeric_limits<double>::epsilon();
  for (int halving = 0; halving <= kMaxHalvings; ++halving, alpha *= 0.5) {
    c_.dv_try.noalias() = c_.dv + alpha * c_.d;
    const PotentialValue trial =
        step_potential(model_, start_, form_, c_.start_length, c_.dv_try, c_.y_try, c_.r_try, &c_.y_try_length);
    ++stats_.force_evals;
    if (halving == 0) {
      first_alpha_ = alpha;
      first_drop_ = phi_.phi - trial.phi;
    }
    bool accept = trial.phi <= phi_.phi + kArmijo * alpha * slope;
    if (!accept && -alpha * slope <= resolvable * phi_.magnitude) {
      c_.rhs = c_.r_try;  // scratch (rebuilt at the next iteration): the trial's filtered residual
      c_.contacts.filter.apply(c_.rhs);
      accept = matrix_dot(c_.rhs, c_.rhs) < r_norm2_;
      if (!accept) return false;  // rounding has the last word: stop here
      if (halving == 0) first_drop_ = std::numeric_limits<double>::quiet_NaN();  // no verdict
    }
    if (accept) {
      alpha_ = alpha;
      c_.dv.swap(c_.dv_try);
      c_.y.swap(c_.y_try);
      c_.y_length.swap(c_.y_try_length);
      c_.r.swap(c_.r_try);
      ++scan_.y_version;
      phi_ = trial;
      return true;
    }
  }
  return false;
}

int particle_steps_over(const Eigen::Matrix3Xd& d, Eigen::Index P, double cap) {
  int over = 0;
  for (Eigen::Index i = 0; i < P; ++i) over += d.col(i).norm() > cap;
  return over;
}

int cap_particle_steps(Eigen::Matrix3Xd& d, Eigen::Index P, double cap) {
  int capped = 0;
  for (Eigen::Index i = 0; i < P; ++i) {
    const double length = d.col(i).norm();
    if (length > cap) {  // (scaling keeps a held particle's share off its normal)
      d.col(i) *= cap / length;
      ++capped;
    }
  }
  return capped;
}

// The direction with each particle's end-position change h |d_i| held within
// ImplicitDef::direction_cap shortest rest lengths (a spring may not turn over within one
// trial), and its slope; the model's curvature along it costs one mat-vec, where any particle
// was capped. Where the capped direction is not downhill (the scaling reweights r . d), CG's.
double NewtonSolve::cap_direction(double slope) {
  capped_ = false;
  const double cap = cfg_.direction_cap * c_.shortest_rest / h_;
  // Counted first: most directions have no particle beyond the cap, and keep CG's uncopied.
  if (particle_steps_over(c_.d, model_.num_particles, cap) == 0) return slope;
  c_.cg.z = c_.d;  // (CG's scratch, free between solves)
  const int capped = cap_particle_steps(c_.d, model_.num_particles, cap);
  const double capped_slope = -matrix_dot(c_.rhs, c_.d);
  trace_("  capped %d particles: slope %.3e -> %.3e\n", capped, slope, capped_slope);
  if (!(capped_slope < 0.0)) {
    c_.d.swap(c_.cg.z);
    return slope;
  }
  c_.A.multiply(c_.A, c_.d, c_.cg.q);
  c_.contacts.filter.apply(c_.cg.q);
  capped_curvature_ = matrix_dot(c_.d, c_.cg.q);
  capped_ = true;
  return capped_slope;
}

// rho = Phi's actual decrease over the quadratic model's at the line search's first trial
// (alpha0 d: the barrier's bound, else d): the trust radius's verdict on the direction. No
// verdict where that decrease is below Phi's rounding (the residual decided). The model's
// curvature d.A d comes from CG's value q(d) = d.A d / 2 + slope (no mat-vec of its own).
void NewtonSolve::update_trust(double slope) {
  const double a = first_alpha_;
  const double curvature = capped_ ? capped_curvature_ : 2.0 * (model_value_ - slope);
  const double predicted = -a * slope - 0.5 * a * a * curvature;
  // (no norm: CG started from a guess, and the region did not apply)
  if (step_norm_ == 0.0 || std::isnan(first_drop_) ||
      !(predicted > 64.0 * std::numeric_limits<double>::epsilon() * phi_.magnitude))
    return;
  const double rho = first_drop_ / predicted;  // (-inf or NaN where the trial's Phi was not finite)
  // (the norms are CG's direction's: the cap is a per-particle bound beneath the radius, and a
  // capped direction that the model described well says the radius may grow)
  trust_.update(rho, a * step_norm_, alpha_ * step_norm_, boundary_ || capped_);
}

}  // namespace clothsim
