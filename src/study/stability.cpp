#include "stability.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include "study_run.h"
#include "task_pool.h"
#include "scene/run_bounds.h"
#include "core/integrators/integrator.h"

namespace clothsim::analysis {
namespace {

constexpr double kNoStep = std::numeric_limits<double>::quiet_NaN();  // no step found (yet)

bool finite_positive(double v) { return v > 0.0 && std::isfinite(v); }

}  // namespace

const char* outcome_name(StabilityOutcome outcome) {
  switch (outcome) {
    case StabilityOutcome::Bracketed: return "bracketed";
    case StabilityOutcome::StableAtMax: return "stable_at_max";
    case StabilityOutcome::UnstableAtMin: return "unstable_at_min";
    case StabilityOutcome::Stopped: return "stopped";
  }
  return "?";
}

const char* failure_name(Failure failure) {
  switch (failure) {
    case Failure::None: return "";
    case Failure::Diverged: return "diverged";
    case Failure::NotConverged: return "not_converged";
  }
  return "?";
}

std::string frame_step_text(const FrameStepResult& r) {
  std::ostringstream line;
  line.precision(4);
  const double per_second = 1.0 / r.dt;
  if (std::abs(per_second - std::round(per_second)) <= 1e-6 * per_second)
    line << "1/" << std::round(per_second) << " s: ";
  else
    line << r.dt << " s: ";
  if (r.stopped) line << "stopped";
  else if (r.failure == Failure::Diverged) line << "diverged at t = " << r.diverged_at << " s";
  else if (r.failure == Failure::NotConverged)
    line << r.unconverged_steps << " of " << r.steps << " steps not converged";
  else if (r.fixed_point_iterations > 0)  // its steps end after K iterations, measured against nothing
    line << "ok, " << r.steps << " steps of " << r.fixed_point_iterations << " fixed-point iteration"
         << (r.fixed_point_iterations == 1 ? "" : "s") << " (no solve to converge)";
  else line << "ok, " << r.steps << " steps converged";
  return line.str();
}

void check(const StabilitySpec& spec) {
  if (spec.integrators.empty()) throw StudyError("no integrators given");
  if (!finite_positive(spec.duration)) throw StudyError("the duration must be a finite number > 0 s");
  if (!finite_positive(spec.min_dt)) throw StudyError("the smallest step tried must be a finite number > 0 s");
  if (!finite_positive(spec.max_dt)) throw StudyError("the largest step tried must be a finite number > 0 s");
  if (!(spec.min_dt < spec.max_dt)) {
    std::ostringstream msg;
    msg << "the smallest step tried (" << spec.min_dt << " s) must be below the largest (" << spec.max_dt << " s)";
    throw StudyError(msg.str());
  }
  const std::string too_long = run_bounds_problem(spec.duration, spec.min_dt, 0.0);
  if (!too_long.empty()) throw StudyError("at the smallest step tried, " + too_long);
  if (spec.max_dt > spec.duration / kMinTrialSteps * (1 + 1e-12)) {
    std::ostringstream msg;
    msg << "the largest step tried (" << spec.max_dt << " s) leaves fewer than " << kMinTrialSteps
        << " steps in T = " << spec.duration << " s, too few for an instability to show; lower it to "
        << spec.duration / kMinTrialSteps << " s or run longer";
    throw StudyError(msg.str());
  }
  // Below ~1e-15 the bracket's ends are neighbouring doubles and bisection cannot narrow it.
  if (!(spec.precision >= 1e-12 && spec.precision < 1.0)) throw StudyError("the precision must be from 1e-12 to 1");
  if (!finite_positive(spec.energy_factor)) throw StudyError("the energy factor must be a finite number > 0");
  if (!finite_positive(spec.max_strain)) throw StudyError("the strain bound must be a finite number > 0");
  if (spec.first_guess < 0.0 || !std::isfinite(spec.first_guess)) throw StudyError("the first guess must be >= 0 s");
}

namespace {

// How a run that was not stopped failed, if it did.
Failure failure_of(const StudyRun& run) {
  if (run.divergence) return Failure::Diverged;
  if (run.totals.unconverged_steps > 0) return Failure::NotConverged;
  return Failure::None;
}

// One search for the largest stable step: trials at the largest step, then a bracket by
// factors of 2 from the first guess, then bisection in log dt. Each trial is a run to T.
class StableStepSearch {
 public:
  StableStepSearch(const Model& model, const MethodSettings& settings, IntegratorKind kind, const StabilitySpec& spec,
                   const std::function<bool()>& stop)
      : model_(model), settings_(settings), kind_(kind), spec_(spec), stop_(stop) {
    model_.divergence.max_energy_factor = spec.energy_factor;  // the study's bounds
    model_.divergence.max_strain = spec.max_strain;
    out_.integrator = kind;
    out_.estimate = estimate_stiffness(model_);
    out_.stable_dt = out_.unstable_dt = kNoStep;
  }

  StabilityLimit run() {
    if (stable(spec_.max_dt)) return finish(StabilityOutcome::StableAtMax);
    if (stopped_) return finish(StabilityOutcome::Stopped);
    double lo = kNoStep, hi = spec_.max_dt;  // lo: stable (once found), hi: unstable
    if (!bracket(lo, hi)) return finish(stopped_ ? StabilityOutcome::Stopped : StabilityOutcome::UnstableAtMin);
    bisect(lo, hi);
    return finish(StabilityOutcome::Bracketed);
  }

 private:
  // One trial: true when the run reached T with every step converged; records the smallest
  // step that failed, and how.
  bool stable(double dt) {
    const StudyRun run = run_to(model_, settings_, kind_, dt, spec_.duration, stop_);
    ++out_.trials;
    out_.cpu_seconds += run.totals.cpu_seconds;
    if (run.stopped) stopped_ = true;
    const Failure failure = failure_of(run);
    if (run.finished && failure == Failure::None) {
      if (!(out_.stable_dt >= dt)) out_.stable_dt = dt;
      return true;
    }
    if (!stopped_ && !(out_.unstable_dt <= dt)) record_failure(dt, run, failure);
    return false;
  }

  void record_failure(double dt, const StudyRun& run, Failure failure) {
    out_.unstable_dt = dt;
    out_.failure = failure;
    std::ostringstream why;
    why.precision(4);
    if (failure == Failure::Diverged)
      why << "at t = " << run.divergence->t << " s: " << run.divergence->reason;
    else
      why << run.totals.unconverged_steps << " of " << run.totals.steps
          << " steps not converged (largest final residual " << run.totals.max_residual << ")";
    out_.reason = why.str();
  }

  // From the first guess by factors of 2 until a stable step lies below an unstable one;
  // false when none is stable down to the smallest step tried (or the search was stopped).
  bool bracket(double& lo, double& hi) {
    double guess = spec_.first_guess > 0.0 ? spec_.first_guess : out_.estimate.dt_with_damping();
    if (!std::isfinite(guess)) guess = spec_.max_dt;
    guess = std::clamp(guess, spec_.min_dt, 0.5 * spec_.max_dt);
    if (stable(guess)) {
      lo = guess;
      for (double h = 2.0 * lo; h < hi && !stopped_; h *= 2.0) (stable(h) ? lo : hi) = h;
      return true;
    }
    hi = guess;
    for (double h = 0.5 * hi; !stopped_; h *= 0.5) {
      if (h <= spec_.min_dt) {  // the last halving lands on min_dt exactly
        (stable(spec_.min_dt) ? lo : hi) = spec_.min_dt;
        break;
      }
      if (stable(h)) {
        lo = h;
        break;
      }
      hi = h;
    }
    return !stopped_ && !std::isnan(lo);
  }

  // In log dt until hi / lo is within the precision, or the midpoint no longer differs from
  // an end in double precision (a precision near 1e-16 would otherwise never end).
  void bisect(double& lo, double& hi) {
    while (!stopped_ && hi / lo > 1.0 + spec_.precision) {
      const double mid = std::sqrt(lo * hi);
      if (!(mid > lo && mid < hi)) break;
      (stable(mid) ? lo : hi) = mid;
    }
  }

  // implicit_euler at one step per frame: reported beside the search, not searched.
  void add_frame_steps() {
    for (double dt : spec_.frame_dts) {
      const StudyRun run = run_to(model_, settings_, kind_, dt, spec_.duration, stop_);
      ++out_.trials;
      out_.cpu_seconds += run.totals.cpu_seconds;
      FrameStepResult r;
      r.dt = dt;
      r.stopped = run.stopped;
      r.failure = failure_of(run);
      r.steps = run.totals.steps;
      r.unconverged_steps = run.totals.unconverged_steps;
      if (run.divergence) r.diverged_at = run.divergence->t;
      const ImplicitDef& implicit = settings_.implicit;
      if (implicit.solver == ImplicitSolver::FixedPoint) r.fixed_point_iterations = implicit.fixed_point_iterations;
      out_.frame_steps.push_back(r);
    }
  }

  StabilityLimit finish(StabilityOutcome outcome) {
    out_.outcome = stopped_ ? StabilityOutcome::Stopped : outcome;
    if (integrator_info(kind_).frame_rate_steps && !stopped_) add_frame_steps();
    return out_;
  }

  Model model_;  // a copy with the study's bounds
  MethodSettings settings_;
  IntegratorKind kind_;
  const StabilitySpec& spec_;
  const std::function<bool()>& stop_;
  StabilityLimit out_;
  bool stopped_ = false;
};

}  // namespace

StabilityLimit largest_stable_dt(const Model& model, const MethodSettings& settings, IntegratorKind kind,
                                 const StabilitySpec& spec, const std::function<bool()>& stop) {
  check(spec);
  return StableStepSearch(model, settings, kind, spec, stop).run();
}

StabilityLimit largest_stable_dt(const Model& model, IntegratorKind kind, const StabilitySpec& spec,
                                 const std::function<bool()>& stop) {
  return largest_stable_dt(model, model.method_defaults(), kind, spec, stop);
}

namespace {

// Where the explicit methods' limits lie beside the Gershgorin bounds: the drape's searches
// found its dampers' rate 2.4x below c_max, its springs' frequency at w_max (docs/cluster.md).
constexpr double kDamperSlack = 2.4;
// An unstable trial stops at its divergence, sooner the farther past the limit; the share
// of a run to T it is counted as matters little (docs/cluster.md).
constexpr double kUnstableShare = 0.3;

StiffnessEstimate likely_stiffness(StiffnessEstimate e) {
  e.c_max /= kDamperSlack;
  return e;
}

// What one step of `kind` at `dt` costs in force evaluations. Implicit Euler's Newton and CG
// work grows with the stiffness the step spans, w_max dt, and with the mesh (CG needs more
// iterations on a finer one): fitted on the drape at 25 x 25 and 50 x 50.
double step_cost(const Model& model, const StiffnessEstimate& e, IntegratorKind kind, double dt) {
  const int evals = nominal_force_evals(kind);
  if (evals > 0) return evals;
  const double spanned = std::isfinite(e.w_max) ? e.w_max * dt : 0.0;
  return 42.0 * (1.0 + 5.6e-5 * static_cast<double>(model.num_particles) * spanned);
}

// The search's trials replayed on a step limit assumed known: the same dts StableStepSearch
// tries (max_dt, the bracket from the first guess, the bisection), each trial's steps times
// their cost, a stable trial running to T and an unstable one kUnstableShare of the way.
class SearchReplay {
 public:
  SearchReplay(double limit, const StabilitySpec& spec, const std::function<double(double)>& per_step)
      : limit_(limit), spec_(spec), per_step_(per_step) {}

  double cost(double guess) {
    if (stable(spec_.max_dt)) return total_;
    double lo = kNoStep, hi = spec_.max_dt;
    guess = std::clamp(std::isfinite(guess) ? guess : spec_.max_dt, spec_.min_dt, 0.5 * spec_.max_dt);
    if (stable(guess)) {
      lo = guess;
      for (double h = 2.0 * lo; h < hi; h *= 2.0) (stable(h) ? lo : hi) = h;
    } else {
      hi = guess;
      for (double h = 0.5 * hi; std::isnan(lo); h *= 0.5) {
        if (h <= spec_.min_dt) {
          if (!stable(spec_.min_dt)) return total_;
          lo = spec_.min_dt;
        } else (stable(h) ? lo : hi) = h;
      }
    }
    while (hi / lo > 1.0 + spec_.precision) {
      const double mid = std::sqrt(lo * hi);
      (stable(mid) ? lo : hi) = mid;
    }
    return total_;
  }

  void add_run(double dt, double share) { total_ += share * (spec_.duration / dt) * per_step_(dt); }
  double total() const { return total_; }

 private:
  bool stable(double dt) {
    const bool ok = dt <= limit_;
    add_run(dt, ok ? 1.0 : kUnstableShare);
    return ok;
  }

  double limit_;
  const StabilitySpec& spec_;
  const std::function<double(double)>& per_step_;
  double total_ = 0.0;
};

}  // namespace

double search_cost(const Model& model, IntegratorKind kind, const StabilitySpec& spec) {
  return search_cost(model, model.method_defaults(), kind, spec);
}

double search_cost(const Model& model, const MethodSettings& settings, IntegratorKind kind, const StabilitySpec& spec) {
  const StiffnessEstimate e = estimate_stiffness(model);
  const double limit = predicted_limit(likely_stiffness(e), kind, settings.implicit);
  const std::function<double(double)> per_step = [&](double dt) { return step_cost(model, e, kind, dt); };
  SearchReplay replay(limit, spec, per_step);
  const double guess = spec.first_guess > 0.0 ? spec.first_guess : e.dt_with_damping();
  replay.cost(guess);
  if (integrator_info(kind).frame_rate_steps)  // its runs at one step per frame, beside the search
    for (double dt : spec.frame_dts) replay.add_run(dt, 1.0);
  return replay.total();
}

MethodSettings case_lane_settings(const StabilityCase& c, std::size_t lane) {
  return lane < c.lane_settings.size() ? c.lane_settings[lane] : c.model->method_defaults();
}

std::vector<StabilityLimit> stability_sweep(const std::vector<StabilityCase>& cases, const StabilitySpec& spec,
                                            const StudyHooks& hooks) {
  std::vector<std::size_t> items(cases.size() * spec.integrators.size());
  for (std::size_t i = 0; i < items.size(); ++i) items[i] = i;
  return stability_sweep_items(cases, spec, items, hooks);
}

std::vector<StabilityLimit> stability_sweep_items(const std::vector<StabilityCase>& cases, const StabilitySpec& spec,
                                                  const std::vector<std::size_t>& items, const StudyHooks& hooks,
                                                  const std::function<void(std::size_t, const StabilityLimit&)>& finished) {
  check(spec);
  const std::size_t per_case = spec.integrators.size();
  const std::size_t total = items.size();
  std::vector<StabilityLimit> limits(total);
  std::vector<bool> done_flags(total, false);
  std::mutex mutex;
  long done = 0;
  parallel_for(total, spec.jobs, [&](std::size_t i) {
    const StabilityCase& c = cases[items[i] / per_case];
    const std::size_t lane = items[i] % per_case;
    StabilityLimit limit =
        largest_stable_dt(*c.model, case_lane_settings(c, lane), spec.integrators[lane], spec, hooks.stop);
    limit.value = c.value;
    limit.lane = lane;
    std::lock_guard<std::mutex> lock(mutex);
    if (limit.outcome == StabilityOutcome::Stopped) return;
    if (finished) finished(items[i], limit);
    limits[i] = std::move(limit);
    done_flags[i] = true;
    ++done;
    if (hooks.progress) hooks.progress(StudyProgress{done, static_cast<long>(total)});
  }, hooks.stop);
  std::vector<StabilityLimit> kept;
  for (std::size_t i = 0; i < total; ++i)
    if (done_flags[i]) kept.push_back(std::move(limits[i]));
  return kept;
}

}  // namespace clothsim::analysis
