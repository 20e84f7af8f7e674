// Backward (implicit) Euler on the whole state:
//     v_{n+1} = v_n + h a(x_{n+1}, v_{n+1}),   x_{n+1} = x_n + h v_{n+1}.
// First order and unconditionally stable: for x'' = -w^2 x its amplification 1 / (1 - z),
// z = i w h, has modulus 1 / sqrt(1 + (w h)^2) < 1, so it loses energy at every step size.
//
// solver: newton (default). The equation solved is step_potential.h's: backward Euler with
// each damper's rate taken over the step, (l_{n+1} - l_n) / h, which makes the residual
//     r(dv) = M dv - h f(x_n + h (v_n + dv), v_n + dv)
// the gradient of a potential Phi(dv) (Gast et al. 2015). It is minimised by Newton's method:
//  - each direction solves H d = -r, H Phi's exact Hessian, by PCG truncated at negative
//    curvature (Nocedal & Wright, Algorithm 7.1): where the cloth buckles and H is indefinite,
//    the iterate before the negative curvature (or the first preconditioned direction) is
//    still downhill. CG's tolerance tightens as r falls (an inexact Newton method, forcing
//    term |r| / scale capped at 0.1). Its preconditioner is block Jacobi while that is cheap
//    and a sparse Cholesky factor of the projected Hessian once the iterations it needs would
//    pay for one (cholesky_preconditioner.h; the choice is by counted work, below);
//  - a backtracking (Armijo) line search on Phi takes the step, so every iterate lowers Phi
//    and the iteration converges from any start at any step size (Nocedal & Wright, ch. 3);
//    where Phi's decrease is below its rounding, the filtered residual decides instead;
//  - contacts with the ground and kinematic spheres are constraints of the minimisation,
//    held by filtering (step_contacts.h), found as an active set.
// It starts from the previous step's dv when there is one (at small steps dv changes little),
// or from the line or the parabola through the last two or three steps' dv where that predicted
// the last step better (first_guess.h). Its Newton matrix is reused across iterations and steps while an iteration
// with it meets the tolerance or contracts the residual (kReuseContraction); the matrix's
// linearisation lives in State, so a copied State continues bit for bit.
// newton_max_iterations = 1 is Baraff & Witkin 1998's step instead: one linear system,
// linearised about the start of the step (y = x_n, dv = -v_n), with the projected Hessian,
// solved to cg_tolerance and taken whole, without line search or active-set rounds.
// The step is converged when |S r|, S the contact filter, is at most newton_tolerance times
// max(|h f(x_n)|, |M dv|) over movable bodies (floored at the rounding level of f: below).
//
// solver: fixed_point. K fixed-point iterations y <- y_n + h F(y) on the whole state
// y = (x, v), from the forward-Euler predictor y = y_n + h F(y_n), with the dampers'
// instantaneous rate (spring_force.h's seed formula). Their fixed point is backward Euler,
// but the iteration only contracts when h |dF/dy| < 1: for the linear test equation K
// iterations give the amplification 1 + z + ... + z^{K+1}, so K = 1 (the course framework's
// "implicit" integrator) has 1 + z + z^2, which on the oscillator (z = i w h) is stable only
// for w h <= 1. It exists so users can see that difference.
//
// StepStats, newton:
//   force_evals        evaluations of Phi and r (each a pass over the springs, as a force
//                      evaluation): 1 at the start + 1 per line-search trial (Baraff &
//                      Witkin: 1 for its step) + 1 each time the held set changes.
//   newton_iterations  linear solves, each preceded by one Hessian assembly (1 = B & W).
//   cg_iterations      PCG iterations summed over those solves (each one block mat-vec, and
//                      one block-diagonal or one factored solve).
//   factorizations     sparse Cholesky factors built (0 where block Jacobi sufficed).
//   residual           the final relative residual |S r| / scale.
//   converged          residual <= newton_tolerance within newton_max_iterations (counted
//                      over the whole step, active-set rounds included).
//   contact_constraints  particles held on a collider's plane at the end of the solve.
// StepStats, fixed_point:
//   force_evals = 1 + K, newton_iterations = K, cg_iterations = 0,
//   residual = |v_K - v_{K-1}| / |v_K - v_n| (how far the last iteration still moved v),
//   converged = true: a fixed number of iterations, with no tolerance to miss.
#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "integrator.h"
#include "core/forces.h"
#include "core/implicit/first_guess.h"
#include "core/implicit/newton_kernels.h"
#include "core/implicit/sparse_system.h"
#include "core/implicit/step_contacts.h"
#include "core/implicit/step_potential.h"
#include "core/linear/cg_kernels.h"  // simd_dot
#include "core/linear/cholesky_preconditioner.h"
#include "core/linear/conjugate_gradient.h"
#include "core/stiffness_estimate.h"

namespace clothsim {

// The sparse pattern and the buffers the Newton solve needs, built once per model (the
// Workspace belongs to one run, so to one model) and resized only if the body count changes.
// Scratch only: nothing here carries from one step to the next.
struct ImplicitCache {
  const Model* model = nullptr;
  double force_scale = 0.0;  // N, sqrt(sum_s (ks_s l0_s)^2): the size of the spring forces' terms
  // The shortest rest length (m; infinite without springs) and the springs' Gershgorin bounds
  // on the fastest frequency and damping rate (analysis/stiffness_estimate.h): what the
  // distance rule for reusing the Newton matrix (kReuseChange) is measured by.
  double shortest_rest = 0.0;
  analysis::StiffnessEstimate stiffness;
  SpringBlockMatrix A;
  std::vector<double> start_length;  // (slots) l_n, by slot (step_lengths)
  // The springs' lengths at y and at y_try (step_potential's end_length; empty where the
  // model's springs are not all in families), swapped with them: a step that ends at y
  // (x_{n+1} = y to the bit, as it does unless a collision or an event moved a particle)
  // starts the next from y_length rather than a pass over the springs.
  std::vector<double> y_length, y_try_length;
  StepContacts contacts;
  Eigen::Matrix3Xd dv, y, r;            // (3 x B) the iterate, its end positions and residual
  Eigen::Matrix3Xd dv_try, y_try, r_try;  // (3 x B) a line-search trial
  Eigen::Matrix3Xd d, rhs;              // (3 x B) the Newton direction and -S r
  Eigen::Matrix3Xd guess;               // (3 x B) an extrapolated first guess (guess_through)
  // 1 / w and 1 / w^2 (0 on immovable bodies) for the inverse masses in mass_of, formed again
  // only when a step's inverse masses differ (a pin or unpin).
  Eigen::VectorXd mass, mass_squared, mass_of;  // (B)
  // The exact Hessian in A: which assembly it is (State::implicit_lin_id; 0 = none, or A holds
  // something else), and whether diag_inverse is A's block-Jacobi inverse.
  std::uint64_t matrix_id = 0;
  bool jacobi_ready = false;
  CgBuffers cg;
  CholeskyPreconditioner factor;  // built and used within one step
};

void ImplicitCacheDeleter::operator()(ImplicitCache* cache) const { delete cache; }

namespace {

// Line search: Armijo's sufficient decrease, halving from the full Newton step.
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 30;
// Active-set rounds (let go / take in) after the first solve of a step.
constexpr int kMaxContactRounds = 4;
// The largest CG forcing term (relative tolerance of a Newton direction).
constexpr double kMaxForcing = 0.1;
// The forcing term is dropped for the absolute tolerance when |r| times it is below this many
// Newton tolerances (above: the finishing solve).
constexpr double kFinishMargin = 10.0;
// The relative residual below which contacts are let go during a solve.
constexpr double kReleaseResidual = 1e-2;
// Every kRetryJacobi-th step starts with block Jacobi even when the last step factored, so a
// run whose steps have become easy stops factoring.
constexpr int kRetryJacobi = 16;
// Reusing the Newton matrix (the Hessian of an earlier iterate, of this step or an earlier
// one): an iteration with it is judged at the next residual. It served if that residual met
// the tolerance or fell to at most kReuseContraction times the one before, with the full step
// taken and CG converged; then the matrix is kept. Otherwise the step assembles afresh at its
// next iteration, and later steps do so too, trying the old matrix again every
// kRetryReuse-th step. An iteration with a reused matrix costs about 0.4 of one that
// assembles (a Phi evaluation and the CG solve, without the assembly), so one that takes the
// residual down 4 times or more is at least as good as an exact one followed by nothing.
// A step tries a reused matrix only while more than kReuseReserve iterations of its budget
// would remain after it, so a reuse that does not serve never costs a step its convergence
// (with newton_max_iterations 2 or 3 the last two iterations are always exact Newton).
constexpr double kReuseContraction = 0.25;
constexpr int kRetryReuse = 16;
constexpr int kReuseReserve = 2;
// ... and only at an iterate whose relative residual is below kReuseResidual, where the step
// left to take is small and any nearby Hessian models it. Far from the solution (a large step's
// first iterations, at residuals near 1) exact Newton's path decides which minimum of Phi the
// step finds, and an undamped crumpled sheet at h = 0.5 s found one of higher energy when
// its first direction came from the last step's matrix.
constexpr double kReuseResidual = 1e-4;
// ... or at an iterate close enough to the matrix's linearisation point (State::implicit_lin_y)
// that the matrix is the Hessian there to within kReuseChange, whatever the residual. Within a
// step the matrix depends on the iterate only through the springs' end positions (the held set
// enters through PCG's filter, not the matrix); across steps also through the start lengths
// l_n of the dampers' term, which move by about h |v| a step and which the distance does not
// see: the bound below is looser by that much, and the judgement after the step catches it. Moved by at most delta, a spring turns by at most
// about 2 delta / l_min, so its block of M^-1 A, of size up to h kd / m + h^2 ks / m, changes by
// at most twice that; summed over a particle's springs (Gershgorin, with the bounds c_max and
// w_max^2 of analysis/stiffness_estimate.h), |M^-1 (A(y) - A)| <= 4 (h c_max + (h w_max)^2)
// delta / l_min to first order. Below the forcing term's cap (kMaxForcing) such a matrix's
// direction is exact Newton's to within what inexact Newton leaves anyway: the same path, which
// is what the residual rule protects at large steps (there h w_max >> 1 and the rule allows
// micrometres, so it seldom acts: the one-step-per-frame table did not change).
// At the drape's 1e-4 s the residual is large for another reason: after the held set changes,
// the first guess misses a fast damped transient for 10-30 steps (relative residuals 1e-3 ..
// 0.05), while the iterate lies within 1e-4 .. 7e-4 m of the last matrix's point, and Newton is
// paced by CG's forcing term, not by nonlinearity (docs/integrators.md, "Small steps"). There
// the rule allows 0.44 mm on a 64 x 64 sheet (1.2 mm at 25 x 25), and a reused matrix contracts the residual as an
// exact one does. (Rest lengths, not current ones: a spring compressed far below its rest
// length turns faster, which the judgement above still catches.)
constexpr double kReuseChange = 0.05;

// CLOTHSIM_NEWTON_TRACE=1 in the environment prints the Newton solve's course on stderr, one
// line per event: each step's start (how its predicted held set differs from the last step's,
// the first guess taken, the distance to the Newton matrix's linearisation point); each
// iterate's relative residual, held contacts and Phi; each solve's CG
// iterations and whether it met negative curvature; each line search's step; each change of
// the held set. A diagnostic for the hard steps (docs/integrators.md, "Implicit Euler at the
// extremes": stiff.yaml's impact at 1/30 s was read off it); it changes no number.
const bool kNewtonTrace = std::getenv("CLOTHSIM_NEWTON_TRACE") != nullptr;

[[gnu::format(printf, 1, 2)]] void trace(const char* format, ...) {
  if (!kNewtonTrace) return;
  std::va_list args;
  va_start(args, format);
  std::vfprintf(stderr, format, args);
  va_end(args);
}

// Names every assembled Newton matrix in the process (State::implicit_lin_id).
std::atomic<std::uint64_t> next_matrix_id{1};
// The largest sparse factor built (its L, cholesky_preconditioner.h): 512 MiB, between a
// 256 x 256 sheet's (424 MiB) and a 300 x 300 sheet's (766 MiB). Larger sheets solve with
// block Jacobi.
constexpr std::size_t kMaxFactorBytes = std::size_t{512} << 20;

ImplicitCache& cache_for(const Model& model, Workspace& ws) {
  if (!ws.implicit) ws.implicit.reset(new ImplicitCache);
  ImplicitCache& c = *ws.implicit;
  if (c.model != &model || c.A.num_bodies() != model.num_bodies() ||
      c.A.num_springs() != model.springs.size()) {
    build_pattern(model, c.A);
    c.y_length.clear();
    c.factor.reset();  // analysed when first needed
    c.matrix_id = 0;
    c.model = &model;
    double sum = 0.0;
    for (std::size_t s = 0; s < model.springs.size(); ++s)
      sum += std::pow(model.springs.ks[s] * model.springs.rest[s], 2);
    c.force_scale = std::sqrt(sum);
    c.shortest_rest = std::numeric_limits<double>::infinity();
    for (double rest : model.springs.rest) c.shortest_rest = std::min(c.shortest_rest, rest);
    c.stiffness = analysis::estimate_stiffness(model);
  }
  return c;
}

// |M dv| over movable bodies, with mass_squared[i] = 1 / w_i^2 (0 where w_i = 0): formed once
// per step, not a division per body at every Newton iteration.
double momentum_norm(const Eigen::VectorXd& mass_squared, const Eigen::Matrix3Xd& dv) {
  return std::sqrt(simd_weighted_norm2(mass_squared.data(), dv.data(), static_cast<std::size_t>(dv.cols())));
}

// |h f| at the iterate: M dv - r over movable bodies (mass[i] = 1 / w_i, 0 where w_i = 0).
double impulse_norm(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& dv,
                    const Eigen::Matrix3Xd& r) {
  return std::sqrt(simd_impulse_norm2(mass.data(), dv.data(), r.data(), static_cast<std::size_t>(dv.cols())));
}

// sum_k a_k b_k over two 3 x B matrices.
double dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return simd_dot(a.data(), b.data(), static_cast<std::size_t>(a.size()));
}

// The Newton iterations of one active set, from the iterate in c (dv, y, r, phi) until the
// filtered residual is below tolerance or the step's iteration budget is spent.
// Returns whether it converged.
// kReuseChange's distance for springs as short as `shortest` and as stiff as `stiffness`.
double reuse_reach(double shortest, const analysis::StiffnessEstimate& stiffness, double h) {
  const double springs = h * stiffness.c_max + std::pow(h * stiffness.w_max, 2);
  return springs > 0.0 ? kReuseChange * shortest / (4.0 * springs) : std::numeric_limits<double>::infinity();
}

class NewtonSolve {
 public:
  // `start` is read as the step's start throughout; only its record of the Newton matrix's
  // linearisation (State::implicit_lin_*) is written, when a matrix is assembled.
  NewtonSolve(const Model& model, State& start, double h, ImplicitCache& c, StepStats& stats)
      : model_(model), start_(start), record_(start), h_(h), cfg_(model.implicit), c_(c), stats_(stats),
        single_step_(cfg_.newton_max_iterations == 1),
        factor_first_(start.implicit_factored && start.step % kRetryJacobi != 0),
        trusted_(start.implicit_lin_trusted) {
    reuse_reach_ = reuse_reach(c_.shortest_rest, c_.stiffness, h);
    // The recorded matrix may serve this step if it was assembled for the same system (the
    // step size and which bodies move: the matrix's rows for immovable ones are removed) and
    // last served well, or as a probe every kRetryReuse-th step. Baraff & Witkin's step is
    // linearised at its own start, always.
    const int B = model.num_bodies();
    reuse_ = !single_step_ && start.implicit_lin_id != 0 && start.implicit_lin_h == h &&
             start.implicit_lin_y.cols() == B &&
             start.implicit_lin_length.size() == slot_count(model.spring_layout, model.springs.size()) &&
             start.implicit_lin_inv_mass.size() == B && start.implicit_lin_inv_mass == start.inv_mass &&
             (trusted_ || start.step % kRetryReuse == 0);
    // A factor serves one step: the next builds its own, so a copied State continues bit for bit.
    c_.factor.invalidate();
  }

  void evaluate() {
    phi_ = step_potential(model_, start_, h_, c_.start_length, c_.dv, c_.y, c_.r, &c_.y_length);
    ++stats_.force_evals;
    ++y_version_;
  }

  // take_in_step_contacts at the iterate's y, unless the last scan saw this y with this held
  // set: it would find what it found then, nothing (the scan is a function of y and the held
  // set; after an accepted line search the loop's next round asked again at the same y).
  bool take_in() {
    if (scanned_y_ == y_version_ && scanned_held_ == held_version_) return false;
    const bool changed = take_in_step_contacts(model_, start_, h_, c_.y, c_.contacts);
    if (changed) ++held_version_;
    scanned_y_ = y_version_;
    scanned_held_ = held_version_;
    return changed;
  }
  // update_step_contacts at the iterate: let go of the pulling ones, then take in.
  bool update_contacts() {
    const bool let_go = let_go_step_contacts(c_.r, c_.contacts);
    if (let_go) ++held_version_;
    return take_in() || let_go;
  }

  void set_scale(double impulse_scale) { impulse_scale_ = impulse_scale; }
  bool factored() const { return factored_; }
  bool trusted() const { return trusted_; }

  // warm: a guess for the first direction (the previous step's dv - the current dv), or null.
  bool iterate(const Eigen::Matrix3Xd* warm) {
    for (;;) {
      c_.rhs = -c_.r;
      c_.contacts.filter.apply(c_.rhs);
      r_norm2_ = dot(c_.rhs, c_.rhs);  // (the line search's too: rhs stays as it is till then)
      const double r_norm = std::sqrt(r_norm2_);
      const double scale = std::max(impulse_scale_, momentum_norm(c_.mass_squared, c_.dv));
      // (0 / 0 where nothing can move, no spring and no body term: nothing to solve, solved)
      stats_.residual = r_norm == 0.0 ? 0.0 : r_norm / scale;
      if (judge_reuse_) {  // the last iteration reused a matrix: did it serve?
        judge_reuse_ = false;
        trusted_ = stats_.residual <= cfg_.newton_tolerance ||
                   (reuse_ok_ && r_norm <= kReuseContraction * reuse_from_);
        if (!trusted_) {
          reuse_ = false;
          ++unserved_;
        }
      }
      trace("newton step %lld iteration %d residual %.3e held %zu phi %.10e\n",
            static_cast<long long>(start_.step), stats_.newton_iterations, stats_.residual,
            c_.contacts.size(), phi_.phi);
      if (stats_.residual <= cfg_.newton_tolerance) return true;
      // Once the iterate is near a solution its contact impulses mean something: let go of the
      // pulling ones now rather than converge with them held (a held particle the cloth would
      // lift compresses its neighbours, and the solve then crawls through buckled states).
      if (stats_.residual < kReleaseResidual && update_contacts()) {
        place_on_planes(c_.contacts, start_, h_, c_.dv);
        evaluate();
        trace("  let go / taken in: held %zu\n", c_.contacts.size());
        continue;
      }
      // (A reused matrix's iteration that did not serve is not charged to the budget: the
      // step gets every exact iteration it would have had without it.)
      if (stats_.newton_iterations - unserved_ >= cfg_.newton_max_iterations ||
          !std::isfinite(stats_.residual))
        return false;

      CgSettings settings;
      settings.max_iterations = cfg_.cg_max_iterations;
      // Inexact Newton: solve only as finely as the residual warrants (forcing term |r| / scale,
      // capped at 0.1: quadratic convergence where the Hessian is exact), and never below what
      // the Newton test resolves. Baraff & Witkin's single step gets no second chance: its
      // system is solved to cg_tolerance (a loose forcing term would accept the warm start
      // itself as the step).
      //
      // Where the forcing term would leave the next residual within kFinishMargin of the
      // tolerance (|r| times the forcing term, |r|^2, is what a Newton step with a nearly exact
      // Hessian leaves), the next Newton iteration would be spent on the forcing term alone: this
      // solve goes down to the absolute tolerance instead (a few CG iterations more, one Newton
      // iteration fewer: at the drape's 1e-4 s, started from the last dv at about 1e-3 with a
      // tolerance of 1e-6, steps converged in 1.06 iterations instead of 1.4 on average).
      const double forcing = std::min(kMaxForcing, stats_.residual);
      const bool finish = forcing * stats_.residual < kFinishMargin * cfg_.newton_tolerance;
      settings.tolerance = single_step_ || finish ? cfg_.cg_tolerance
                                                  : std::max(cfg_.cg_tolerance, forcing);
      settings.absolute_tolerance = 0.1 * cfg_.newton_tolerance * scale;
      settings.b_norm = r_norm;  // |rhs|, which solve_pcg would compute again
      const double slope = direction(settings, warm);
      warm = nullptr;
      ++stats_.newton_iterations;
      if (reused_) {  // judged at the next residual (above)
        judge_reuse_ = true;
        reuse_from_ = r_norm;
      }
      if (!(slope < 0.0) || (!single_step_ && !line_search(slope))) {
        // A reused matrix that gives no descent or no step is not a verdict on the iterate:
        // assemble at it and go on. With the exact Hessian it is (a non-finite system, or
        // rounding has the last word).
        if (!reused_) return false;
        judge_reuse_ = false;
        trusted_ = reuse_ = false;
        ++unserved_;
        continue;
      }

      if (single_step_) {  // Baraff & Witkin: the linearised step, whole
        c_.dv += c_.d;
        evaluate();
        continue;  // measures the residual, then stops at the budget
      }
      reuse_ok_ = reuse_ok_ && alpha_ == 1.0;
      // A particle the step took inside a collider is held from here on (letting go waits
      // until the residual is small, when the impulses mean something: above).
      trace("  line search: step %.3g, slope %.3e, reused matrix %d\n", alpha_, slope, reused_ ? 1 : 0);
      if (take_in()) {
        place_on_planes(c_.contacts, start_, h_, c_.dv);
        evaluate();
        trace("  taken in: held %zu\n", c_.contacts.size());
      }
    }
  }

 private:
  // The Newton direction d (in c_.d) for the system at the iterate, and its slope r . d:
  // truncated PCG on the exact Hessian (Baraff & Witkin's single step: the projected one).
  // Where the cloth buckles and H is indefinite, CG stops at the negative curvature with the
  // iterate before it, still a descent direction (Nocedal & Wright, Algorithm 7.1), and the
  // line search takes it from there.
  //
  // The preconditioner is chosen by cost, as renting against buying: block Jacobi while the
  // step's Jacobi iterations cost less than a sparse factorisation, then the factor
  // (cholesky_preconditioner.h), kept while the iterations spent with it since it was built
  // cost less than building it again.
  double direction(CgSettings settings, const Eigen::Matrix3Xd* warm) {
    // The block-Jacobi preconditioner is formed only for solves that use it (below).
    reused_ = reuse_ && (stats_.residual < kReuseResidual || near_linearisation()) &&
              cfg_.newton_max_iterations - (stats_.newton_iterations - unserved_) > kReuseReserve;
    if (!reused_) {
      assemble_step_hessian(model_, start_.inv_mass, h_, c_.start_length, c_.y, single_step_, c_.A, false);
      ++stats_.assemblies;
      c_.jacobi_ready = false;
      c_.matrix_id = 0;
      if (!single_step_) {  // recorded in State for later iterations and steps to reuse
        c_.matrix_id = next_matrix_id.fetch_add(1, std::memory_order_relaxed);
        record_.implicit_lin_y = c_.y;
        record_.implicit_lin_length = c_.start_length;
        record_.implicit_lin_inv_mass = start_.inv_mass;
        record_.implicit_lin_h = h_;
        record_.implicit_lin_id = c_.matrix_id;
      }
    } else if (c_.matrix_id != start_.implicit_lin_id) {
      // The recorded matrix, which this Workspace does not hold: rebuilt from State.
      assemble_step_hessian(model_, start_.implicit_lin_inv_mass, start_.implicit_lin_h,
                            start_.implicit_lin_length, start_.implicit_lin_y, false, c_.A, false);
      ++stats_.assemblies;
      c_.jacobi_ready = false;
      c_.matrix_id = start_.implicit_lin_id;
    }
    if (!c_.factor.analysed()) c_.factor.analyse(c_.A, kMaxFactorBytes);
    // A factor past kMaxFactorBytes is never built (block Jacobi throughout): the memory a run
    // needs stays within what memory_estimate.h promises, whatever the sheet's size.
    const bool affordable = c_.factor.factor_bytes() <= kMaxFactorBytes;
    const double factor_cost = c_.factor.factor_cost();
    if (affordable && (c_.factor.ready() ? factor_work_ > factor_cost : factor_first_)) factorize();
    if (!c_.factor.ready() && !c_.jacobi_ready) {
      invert_diagonal(c_.A);
      c_.jacobi_ready = true;
    }

    settings.from_guess = warm != nullptr;
    if (warm && warm != &c_.d) c_.d = *warm;
    if (c_.factor.ready() || !affordable) {
      solve(settings);
    } else {
      // Jacobi until the step's Jacobi work would pay for a factorisation; if the solve is not
      // done by then, factor and go on from where it stopped.
      // (clamped only so that the cast cannot overflow: an unaffordable factor never gets here)
      const int cap = static_cast<int>(std::clamp(std::ceil(factor_cost - jacobi_work_), 1.0, 1e9));
      settings.max_iterations = std::min(settings.max_iterations, cap);
      const CgResult cg = solve(settings);
      if (!cg.converged && !cg.negative_curvature && cg.iterations >= cap && factorize()) {
        settings.max_iterations = cfg_.cg_max_iterations;
        settings.from_guess = true;  // a descent direction already: CG only improves on it
        solve(settings);
      }
    }
    return -dot(c_.rhs, c_.d);  // r . d (d is filtered)
  }

  // Whether every particle's end position at the iterate lies within reuse_reach_ of the
  // recorded linearisation point (kReuseChange; the spheres have no springs: a kinematic one
  // moving on changes nothing in the matrix).
  bool near_linearisation() const {
    const std::size_t P = static_cast<std::size_t>(model_.num_particles);
    if (P == 0 || reuse_reach_ == std::numeric_limits<double>::infinity()) return true;
    // (NaN: not near)
    return simd_max_distance2(c_.y.data(), start_.implicit_lin_y.data(), P) <= reuse_reach_ * reuse_reach_;
  }

  CgResult solve(const CgSettings& settings) {
    const bool factored = c_.factor.ready();
    const CgResult cg = solve_pcg(c_.A, c_.rhs, c_.d, settings, c_.cg, &c_.contacts.filter,
                                  factored ? &c_.factor : nullptr);
    reuse_ok_ = cg.converged;
    trace("  cg: %d iterations, converged %d, negative curvature %d, relative residual %.2e, factored %d\n",
          cg.iterations, cg.converged ? 1 : 0, cg.negative_curvature ? 1 : 0, cg.relative_residual,
          factored ? 1 : 0);
    stats_.cg_iterations += cg.iterations;
    if (factored) stats_.factored_cg_iterations += cg.iterations;
    if (factored) factor_work_ += cg.iterations * (1.0 + c_.factor.solve_cost());
    else jacobi_work_ += cg.iterations;
    return cg;
  }

  bool factorize() {
    factored_ = true;
    factor_work_ = 0.0;
    ++stats_.factorizations;
    return c_.factor.factorize(c_.A, c_.contacts.filter);
  }

  // Armijo backtracking along d from dv; on success the trial becomes the iterate.
  bool line_search(double slope) {
    double alpha = 1.0;
    alpha_ = 0.0;
    const double r_norm2 = r_norm2_;
    for (int halving = 0; halving <= kMaxHalvings; ++halving, alpha *= 0.5) {
      c_.dv_try.noalias() = c_.dv + alpha * c_.d;
      const PotentialValue trial =
          step_potential(model_, start_, h_, c_.start_length, c_.dv_try, c_.y_try, c_.r_try, &c_.y_try_length);
      ++stats_.force_evals;
      bool accept = trial.phi <= phi_.phi + kArmijo * alpha * slope;
      // Near the solution the decrease falls below what Phi's rounding resolves (its terms
      // are far larger than their changes): there the filtered residual decides.
      const double resolvable = 64.0 * std::numeric_limits<double>::epsilon() * phi_.magnitude;
      if (!accept && -alpha * slope <= resolvable) {
        c_.rhs = c_.r_try;  // scratch (rebuilt at the next iteration): the trial's filtered residual
        c_.contacts.filter.apply(c_.rhs);
        accept = dot(c_.rhs, c_.rhs) < r_norm2;
        if (!accept) return false;  // rounding has the last word: stop here
      }
      if (accept) {
        alpha_ = alpha;
        c_.dv.swap(c_.dv_try);
        c_.y.swap(c_.y_try);
        c_.y_length.swap(c_.y_try_length);
        c_.r.swap(c_.r_try);
        ++y_version_;
        phi_ = trial;
        return true;
      }
    }
    return false;
  }

  const Model& model_;
  const State& start_;
  State& record_;  // the same State: its implicit_lin_* only
  double h_;
  const ImplicitDef& cfg_;
  ImplicitCache& c_;
  StepStats& stats_;
  PotentialValue phi_;
  double impulse_scale_ = 0.0;
  const bool single_step_;     // newton_max_iterations = 1: Baraff & Witkin's step
  const bool factor_first_;    // the last step needed the factor: build it at the first solve
  bool factored_ = false;      // this step built a factor
  double jacobi_work_ = 0.0;   // block-Jacobi PCG iterations this step
  double factor_work_ = 0.0;   // the same units spent with the factor since it was built
  // Reuse of the Newton matrix (kReuseContraction):
  bool trusted_;               // the recorded matrix served when last tried
  bool reuse_ = false;         // the next direction may use the matrix in hand
  bool reused_ = false;        // the last direction did
  double reuse_reach_ = 0.0;   // m: how far from its linearisation point the matrix may be reused
  bool judge_reuse_ = false;   // the next residual judges the last direction's matrix
  bool reuse_ok_ = false;      // that direction's CG converged and its full step was taken
  double reuse_from_ = 0.0;    // |S r| before it
  int unserved_ = 0;           // iterations with a reused matrix that did not serve
  double alpha_ = 0.0;         // the last line search's step
  double r_norm2_ = 0.0;       // |S r|^2 at the iterate
  // The contact scan's inputs, counted: y_version_ changes with c_.y, held_version_ with the
  // held set; scanned_* are the pair the last take-in scan saw.
  std::uint64_t y_version_ = 0, held_version_ = 0;
  std::uint64_t scanned_y_ = ~std::uint64_t{0}, scanned_held_ = ~std::uint64_t{0};
};

// The trace's line at a step's start: how the predicted held set differs from the last step's,
// which first guess was taken, and how far the start iterate's particles lie from the recorded
// Newton matrix's linearisation point (largest, m; -1: none recorded).
void trace_step_start(const Model& model, const State& state, const ImplicitCache& c, const char* guess) {
  std::vector<char> before(model.num_bodies(), 0), now(model.num_bodies(), 0);
  for (int b : state.implicit_held) before[b] = 1;
  for (int b : c.contacts.filter.body) now[b] = 1;
  int added = 0, dropped = 0;
  for (int b = 0; b < model.num_bodies(); ++b) {
    added += now[b] && !before[b];
    dropped += before[b] && !now[b];
  }
  const Eigen::Index P = model.num_particles;
  const double far = state.implicit_lin_y.cols() != model.num_bodies() || P == 0 ? -1.0
      : (c.y.leftCols(P) - state.implicit_lin_y.leftCols(P)).colwise().norm().maxCoeff();
  trace("newton step %lld start: held +%d -%d, guess %s, from the matrix's point %.3e m\n",
        static_cast<long long>(state.step), added, dropped, guess, far);
}

StepStats newton_step(const Model& model, State& state, double h, Workspace& ws) {
  const ImplicitDef& cfg = model.implicit;
  ImplicitCache& c = cache_for(model, ws);
  const Eigen::VectorXd& w = state.inv_mass;
  const int B = model.num_bodies();
  StepStats stats;

  // The start of the step: spring lengths l_n (and so the strain of the state we start from),
  // the contacts predicted from the previous step's dv.
  // (from the last step's end, where the state starts exactly there: the same lengths, bit
  // for bit, without the pass)
  const bool ended_here = !c.y_length.empty() && c.y.cols() == B &&
                          std::memcmp(c.y.data(), state.x.data(), sizeof(double) * 3 * B) == 0;
  if (ended_here) {
    c.start_length.swap(c.y_length);
    stats.start_strain = step_strain(model, c.start_length);
  } else {
    stats.start_strain = step_lengths(model, state.x, c.start_length);
  }
  c.y_length.clear();  // describes no y until the next evaluation
  const DvHistory past(state, B);
  const bool have_guess = past.count > 0;
  const bool baraff_witkin = cfg.newton_max_iterations == 1;
  // The first guess: the last step's dv, or the line or parabola through the last steps' dv
  // where that predicted the last step better (first_guess.h). (Baraff & Witkin's step is
  // warm-started in CG from the last dv, as it always was.)
  const int order = baraff_witkin || !have_guess ? 0 : std::min(state.implicit_guess_order, past.count - 1);
  if (order > 0) guess_through(past, order, c.guess);
  const Eigen::Matrix3Xd* guess = !have_guess ? nullptr : order > 0 ? &c.guess : &state.implicit_dv;
  predict_step_contacts(model, state, h, guess, c.contacts);
  if (c.mass_of.size() != B || c.mass_of != w) {
    c.mass_of = w;
    c.mass.resize(B);
    c.mass_squared.resize(B);
    for (int i = 0; i < B; ++i) {
      c.mass[i] = w[i] != 0.0 ? 1.0 / w[i] : 0.0;
      c.mass_squared[i] = w[i] != 0.0 ? 1.0 / (w[i] * w[i]) : 0.0;
    }
  }

  // Baraff & Witkin's step starts at y = x_n (dv = -v_n on movable bodies). A full solve
  // starts from the previous step's dv when there is one: at the small steps explicit methods
  // need, dv changes little from step to step, and Newton starts most of the way there.
  // Either way held particles are moved onto their planes.
  const bool from_guess = have_guess && !baraff_witkin;
  if (from_guess) c.dv = *guess;
  else c.dv = -state.v;
  for (int i = 0; i < B; ++i)
    if (w[i] == 0.0) c.dv.col(i).setZero();
  place_on_planes(c.contacts, state, h, c.dv);
  NewtonSolve newton(model, state, h, c, stats);
  newton.evaluate();
  if (kNewtonTrace)
    trace_step_start(model, state, c, !guess ? "none" : order == 2 ? "parabola" : order == 1 ? "line" : "last dv");

  // What the residual is measured against: the step's impulse |h f| at the start or its
  // momentum change |M dv|, floored where f itself is only known to rounding (a spring force
  // is the difference of terms of size ks l0, so its rounding error is ~eps ks l0): below
  // 64 eps h |ks l0| no iteration can reduce |r|, and a state at rest must not read as
  // unconverged for it.
  constexpr double kRoundingFactor = 64.0 * std::numeric_limits<double>::epsilon();
  const double scale_floor = kRoundingFactor * h * c.force_scale / cfg.newton_tolerance;
  newton.set_scale(std::max(impulse_norm(c.mass, c.dv, c.r), scale_floor));

  // Baraff & Witkin's direction is warm-started from the previous step's dv in CG instead.
  Eigen::Matrix3Xd* warm = nullptr;
  if (have_guess && baraff_witkin) {
    c.d = *guess - c.dv;
    for (int i = 0; i < B; ++i)
      if (w[i] == 0.0) c.d.col(i).setZero();
    warm = &c.d;
  }
  stats.converged = newton.iterate(warm);
  // Active-set rounds: let go of pulling contacts, take in penetrating particles, resume.
  for (int round = 0; !baraff_witkin && round < kMaxContactRounds; ++round) {
    if (!newton.update_contacts()) break;
    trace("  active-set round %d: held %zu\n", round, c.contacts.size());
    place_on_planes(c.contacts, state, h, c.dv);
    newton.evaluate();
    stats.converged = newton.iterate(nullptr);
  }
  stats.contact_constraints = static_cast<int>(c.contacts.size());
  state.implicit_factored = newton.factored();
  if (!baraff_witkin) state.implicit_lin_trusted = newton.trusted();

  // v_{n+1} = v_n + dv (dv = 0 for immovable bodies), x_{n+1} = x_n + h v_{n+1}
  simd_finish_step(state.x.data(), state.v.data(), c.dv.data(), h, static_cast<std::size_t>(c.dv.size()));
  respond_to_step_contacts(model, c.contacts, c.r, state);
  // Which guess the solution lay closest to decides the next step's.
  state.implicit_guess_order = baraff_witkin ? 0 : next_guess_order(past, c.dv);
  state.implicit_dv_before2.swap(state.implicit_dv_before);
  state.implicit_dv_before.swap(state.implicit_dv);
  state.implicit_dv = c.dv;
  state.implicit_held = c.contacts.filter.body;
  return stats;
}

StepStats fixed_point_step(const Model& model, State& state, double h, Workspace& ws) {
  const int K = model.implicit.fixed_point_iterations;
  const Eigen::VectorXd& w = state.inv_mass;
  StepStats stats;

  // Predictor: forward Euler, y^0 = y_n + h F(y_n), held in (x1, v1).
  stats.start_strain = accelerations(model, state.x, state.v, w, ws.a);
  ++stats.force_evals;
  ws.x1.noalias() = state.x + h * state.v;
  ws.v1.noalias() = state.v + h * ws.a;
  for (int k = 0; k < K; ++k) {
    // y^{k+1} = y_n + h F(y^k), written into (x2, v2) then swapped in (no copy, no allocation).
    accelerations(model, ws.x1, ws.v1, w, ws.a1);
    ++stats.force_evals;
    ws.x2.noalias() = state.x + h * ws.v1;
    ws.v2.noalias() = state.v + h * ws.a1;
    ws.x1.swap(ws.x2);
    ws.v1.swap(ws.v2);
  }
  stats.newton_iterations = K;
  if (K > 0) {  // v2 now holds the previous iterate
    const double moved = (ws.v1 - state.v).norm();
    const double last = (ws.v1 - ws.v2).norm();
    stats.residual = last == 0.0 ? 0.0 : last / moved;
  }
  state.x.swap(ws.x1);
  state.v.swap(ws.v1);
  return stats;
}

}  // namespace

double implicit_reuse_reach(const Model& model, double h) {
  double shortest = std::numeric_limits<double>::infinity();
  for (double rest : model.springs.rest) shortest = std::min(shortest, rest);
  return reuse_reach(shortest, analysis::estimate_stiffness(model), h);
}

StepStats implicit_euler_step(const Model& model, State& state, double h, Workspace& ws) {
  switch (model.implicit.solver) {
    case ImplicitSolver::Newton: return newton_step(model, state, h, ws);
    case ImplicitSolver::FixedPoint: return fixed_point_step(model, state, h, ws);
  }
  return newton_step(model, state, h, ws);
}

}  // namespace clothsim
