#include "work_precision.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>

#include "reference.h"
#include "work_precision_shard.h"
#include "study_run.h"
#include "task_pool.h"
#include "core/integrators/integrator.h"
#include "scene/run_bounds.h"

namespace clothsim::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string seconds_text(double s) {
  std::ostringstream out;
  out.precision(6);
  out << s << " s";
  return out.str();
}

// Steps of `dt` in T when dt divides T, else 0.
std::int64_t whole_steps(double T, double dt) {
  const double n = T / dt;
  const double rounded = std::round(n);
  return rounded >= 1.0 && std::abs(n - rounded) <= 1e-9 * rounded ? static_cast<std::int64_t>(rounded) : 0;
}

}  // namespace

double cost_estimate(IntegratorKind kind, double T, double dt) {
  const int evals = nominal_force_evals(kind);
  return (T / dt) * (evals > 0 ? evals : 8);  // an implicit step: a few Newton/CG rounds
}

double point_cost(const WorkPrecisionPoint& p, double T) {
  if (p.tolerance <= 0.0) return cost_estimate(p.integrator, T, p.dt);
  // A pair of order q takes steps of about tol^(1/(q+1)) (local error control), from about 1e4
  // steps a second at 1e-6 on the drapes: a scheduling guess, nothing more.
  const double q = integrator_info(p.integrator).order;
  return T * 1e4 * std::pow(1e-6 / p.tolerance, 1.0 / (q + 1.0)) * std::max(1, nominal_force_evals(p.integrator));
}

StudyRun run_point(const Model& model, const WorkPrecisionSpec& spec, const WorkPrecisionPoint& p,
                   const std::function<bool()>& stop, const Sampling& sampling) {
  MethodSettings settings = lane_settings(spec, p.lane, model);
  if (p.tolerance > 0.0) settings.adaptive.rtol = settings.adaptive.atol = p.tolerance;  // this point's error control
  return run_to(model, settings, p.integrator, p.dt, spec.duration, stop, sampling);
}

std::vector<double> sample_times(const WorkPrecisionSpec& spec) {
  const double T = spec.duration;
  int K = kMaxSamples;
  for (; K > 1; --K)
    if (std::all_of(spec.dts.begin(), spec.dts.end(), [&](double dt) { return lands_on(T / K, dt); })) break;
  std::vector<double> times;
  for (int k = 1; k < K; ++k) times.push_back(T * k / K);
  times.push_back(T);  // exactly
  return times;
}

void judge_error(WorkPrecisionPoint& p, bool over_time) {
  p.rms_error = over_time ? p.rms_error_over_time : p.rms_error_at_end;
  p.max_error = over_time ? p.max_error_over_time : p.max_error_at_end;
}

std::string lane_name(const WorkPrecisionSpec& spec, std::size_t i) {
  return i < spec.lane_names.size() ? spec.lane_names[i] : std::string(integrator_name(spec.integrators[i]));
}

MethodSettings lane_settings(const WorkPrecisionSpec& spec, std::size_t i, const Model& model) {
  return i < spec.lane_settings.size() ? spec.lane_settings[i] : model.method_defaults();
}

std::vector<WorkPrecisionPoint> planned_points(const WorkPrecisionSpec& spec) {
  std::vector<WorkPrecisionPoint> points;
  for (std::size_t lane = 0; lane < spec.integrators.size(); ++lane) {
    if (integrator_info(spec.integrators[lane]).adaptive) {
      for (double tol : spec.tolerances) {  // loosest first, as the steps go largest last
        WorkPrecisionPoint p;
        p.integrator = spec.integrators[lane];
        p.lane = lane;
        p.dt = spec.first_step > 0.0 ? spec.first_step : spec.dts.front();
        p.tolerance = tol;
        p.rms_error = p.max_error = p.rms_error_at_end = p.max_error_at_end = kNaN;
        p.rms_error_over_time = p.max_error_over_time = kNaN;
        points.push_back(p);
      }
      continue;
    }
    for (double dt : steps_of(spec, spec.integrators[lane])) {
      WorkPrecisionPoint p;
      p.integrator = spec.integrators[lane];
      p.lane = lane;
      p.dt = dt;
      p.frame_step = std::find(spec.dts.begin(), spec.dts.end(), dt) == spec.dts.end();
      p.rms_error = p.max_error = p.rms_error_at_end = p.max_error_at_end = kNaN;
      p.rms_error_over_time = p.max_error_over_time = kNaN;
      points.push_back(p);
    }
  }
  return points;
}

WorkPrecisionPoint measured_point(WorkPrecisionPoint p, const StudyRun& run, const Model& model,
                                  const State* reference) {
  p.finished = run.finished;
  p.diverged = run.divergence.has_value();
  if (p.diverged) p.diverged_at = run.divergence->t, p.reason = run.divergence->reason;
  p.steps = run.totals.steps;
  p.force_evals = run.totals.force_evals;
  p.newton_iterations = run.totals.newton_iterations;
  p.cg_iterations = run.totals.cg_iterations;
  p.unconverged_steps = run.totals.unconverged_steps;
  p.rejected_steps = run.totals.rejected_steps;
  p.wrong = run.totals.wrong.has_value();
  if (p.wrong) p.wrong_at = run.totals.wrong->t, p.wrong_reason = run.totals.wrong->reason;
  p.wall_seconds = run.totals.sim_seconds;
  p.cpu_seconds = run.totals.cpu_seconds;
  if (p.finished && reference) {
    const PositionError e = position_error(model, run.final_state.x, reference->x, reference->inv_mass);
    p.rms_error_at_end = e.rms;
    p.max_error_at_end = e.max;
  }
  return p;
}

// The steps `kind` runs: the common list, and for implicit Euler the frame-rate steps too.
std::vector<double> steps_of(const WorkPrecisionSpec& spec, IntegratorKind kind) {
  std::vector<double> dts = spec.dts;
  if (integrator_info(kind).frame_rate_steps) {
    for (double dt : spec.frame_dts)
      if (std::find(dts.begin(), dts.end(), dt) == dts.end()) dts.push_back(dt);
    std::sort(dts.begin(), dts.end());
  }
  return dts;
}

WorkPrecisionSpec checked(WorkPrecisionSpec spec) {
  if (spec.integrators.empty()) throw StudyError("no integrators given");
  if (spec.dts.empty()) throw StudyError("no step sizes given (an empty list)");
  if (!(spec.duration > 0.0) || !std::isfinite(spec.duration))
    throw StudyError("the duration must be a finite number > 0 s, got " + seconds_text(spec.duration));
  for (double dt : spec.frame_dts) spec.dts.push_back(dt);  // checked alike, split again below
  for (double dt : spec.dts) {
    if (!(dt > 0.0) || !std::isfinite(dt))
      throw StudyError("step size " + seconds_text(dt) + " is not a finite number > 0");
    if (whole_steps(spec.duration, dt) == 0) {
      std::ostringstream msg;
      msg.precision(6);
      msg << dt << " does not divide the duration " << spec.duration << " s (" << spec.duration
          << " / " << dt << " = " << spec.duration / dt
          << "); choose steps that divide it, or a --duration they divide";
      throw StudyError(msg.str());
    }
  }
  spec.dts.resize(spec.dts.size() - spec.frame_dts.size());
  std::sort(spec.frame_dts.begin(), spec.frame_dts.end());
  spec.frame_dts.erase(std::unique(spec.frame_dts.begin(), spec.frame_dts.end()), spec.frame_dts.end());
  std::sort(spec.dts.begin(), spec.dts.end());
  for (std::size_t i = 1; i < spec.dts.size(); ++i)
    if (spec.dts[i] == spec.dts[i - 1]) throw StudyError("step size " + seconds_text(spec.dts[i]) + " is listed twice");
  if (!spec.lane_names.empty() && spec.lane_names.size() != spec.integrators.size())
    throw StudyError("lane names: one per integrator, or none");
  if (!spec.lane_settings.empty() && spec.lane_settings.size() != spec.integrators.size())
    throw StudyError("lane settings: one per integrator, or none");
  for (std::size_t i = 0; i < spec.integrators.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (lane_name(spec, i) == lane_name(spec, j))
        throw StudyError("integrator " + lane_name(spec, i) + " is listed twice");
  std::sort(spec.tolerances.begin(), spec.tolerances.end(), std::greater<>());
  for (std::size_t i = 0; i < spec.tolerances.size(); ++i) {
    std::ostringstream tol;
    tol << spec.tolerances[i];
    if (!(spec.tolerances[i] > 0.0 && spec.tolerances[i] < 1.0))
      throw StudyError("tolerance " + tol.str() + " is not a number in (0, 1)");
    if (i > 0 && spec.tolerances[i] == spec.tolerances[i - 1]) throw StudyError("tolerance " + tol.str() + " is listed twice");
  }
  const bool adaptive_lane = std::any_of(spec.integrators.begin(), spec.integrators.end(),
                                         [](IntegratorKind k) { return integrator_info(k).adaptive; });
  if (adaptive_lane && spec.tolerances.empty()) throw StudyError("an adaptive lane needs tolerances to sweep");
  if (!(spec.first_step >= 0.0) || !std::isfinite(spec.first_step))
    throw StudyError("the first trial step must be a finite number >= 0 s");
  if (spec.reference_refinement < 1) throw StudyError("the reference refinement must be >= 1");
  if (!(spec.reference_margin > 0.0)) throw StudyError("the reference margin must be > 0");
  if (!(spec.reference_tolerance > 0.0)) throw StudyError("the reference tolerance must be > 0");
  // The finest run is the second reference, at half the smallest step over the refinement.
  const std::string too_long =
      run_bounds_problem(spec.duration, 0.5 * spec.dts.front() / spec.reference_refinement, 0.0);
  if (!too_long.empty()) throw StudyError("the finest reference run: " + too_long);
  return spec;
}

PositionError position_error(const Model& model, const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b,
                             const Eigen::VectorXd& free_in_b) {
  PositionError e;
  double sum_sq = 0.0;
  int count = 0;
  for (int p = 0; p < model.num_particles; ++p) {
    if (!(free_in_b[p] > 0.0)) continue;  // pinned at T: its error is zero by construction
    const double d = (a.col(p) - b.col(p)).norm();
    sum_sq += d * d;
    e.max = std::max(e.max, d);
    ++count;
  }
  e.rms = count > 0 ? std::sqrt(sum_sq / count) : 0.0;
  return e;
}

namespace {

// The least-squares slope over the finished common-step points `take` accepts.
template <class Take>
double fitted_order(const std::vector<WorkPrecisionPoint>& points, Take take) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (const WorkPrecisionPoint& p : points) {
    if (!take(p) || p.frame_step || !p.finished || p.unresolved || !(p.rms_error > 0.0)) continue;
    const double x = std::log(p.tolerance > 0.0 ? p.tolerance : p.dt), y = std::log(p.rms_error);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
    ++n;
  }
  if (n < 2) return kNaN;
  const double denom = n * sxx - sx * sx;
  return denom != 0.0 ? (n * sxy - sx * sy) / denom : kNaN;
}

}  // namespace

double convergence_order(const std::vector<WorkPrecisionPoint>& points, IntegratorKind kind) {
  return fitted_order(points, [&](const WorkPrecisionPoint& p) { return p.integrator == kind; });
}

std::vector<ParetoLevel> pareto_front(const std::vector<WorkPrecisionPoint>& points) {
  const auto usable = [](const WorkPrecisionPoint& p) {
    return p.finished && !p.diverged && !p.wrong && p.unconverged_steps == 0 && !p.unresolved &&
           std::isfinite(p.rms_error) && p.rms_error > 0.0;
  };
  double smallest = INFINITY;
  for (const WorkPrecisionPoint& p : points)
    if (usable(p)) smallest = std::min(smallest, p.rms_error);
  std::vector<ParetoLevel> front;
  for (double level = 1e-1; level >= smallest && level > 1e-300; level /= 10.0) {
    std::size_t best = points.size();
    for (std::size_t i = 0; i < points.size(); ++i)
      if (usable(points[i]) && points[i].rms_error <= level &&
          (best == points.size() || points[i].cpu_seconds < points[best].cpu_seconds))
        best = i;
    if (best < points.size()) front.push_back({level, best});
  }
  return front;
}

double lane_convergence_order(const std::vector<WorkPrecisionPoint>& points, std::size_t lane) {
  return fitted_order(points, [&](const WorkPrecisionPoint& p) { return p.lane == lane; });
}

namespace {

// The smallest error resolved (NaN when none).
double smallest_resolved(const std::vector<WorkPrecisionPoint>& points) {
  double smallest = kNaN;
  for (const WorkPrecisionPoint& p : points)
    if (p.finished && !p.unresolved && !(smallest <= p.rms_error)) smallest = p.rms_error;
  return smallest;
}

// Whether a free particle of `s` lies within two contact margins of a sphere or the ground.
bool cloth_touches(const Model& model, const State& s) {
  const double reach = 2.0 * model.collision.margin;
  for (int p = 0; p < model.num_particles; ++p) {
    if (!(s.inv_mass[p] > 0.0)) continue;
    if (model.has_ground && s.x(1, p) <= model.ground.height + reach) return true;
    for (int k = 0; k < model.num_spheres; ++k)
      if ((s.x.col(p) - s.x.col(model.sphere_body(k))).norm() <= model.sphere_radius[k] + reach) return true;
  }
  return false;
}

// The reference's verdict: finished, and halving its step (or tightening its tolerance) moved it
// by less than the margin times the smallest error reported; `failure` says why not.
// The key of bench's reference in the cache: everything its two runs depend on (the model as
// built, the method and its tolerances or steps, T, the sample times, the build).
std::string reference_key(const Model& model, const WorkPrecisionSpec& spec) {
  std::ostringstream key;
  key.precision(17);
  key << "bench reference\nmodel " << model_digest(model) << "\n";
  if (uses_adaptive_reference(model, spec))
    key << "dopri5 tolerance " << spec.reference_tolerance << " tightening " << kReferenceTightening;
  else
    key << integrator_name(spec.reference_integrator) << " dt " << spec.dts.front() / spec.reference_refinement
        << " and half";
  const std::vector<double> times = sample_times(spec);
  Digest digest;
  for (double t : times) digest.number(t);
  key << "\nduration " << spec.duration << "\nsamples " << times.size() << " " << digest.hex() << "\nbuild "
      << build_identity() << "\n";
  return key.str();
}

// The reference from the cache when it holds this one, else run and, when both runs finished,
// stored (its payload: the two runs' totals, then reference_text, exact).
ShardReference cached_reference(const Model& model, const WorkPrecisionSpec& spec, const StudyHooks& hooks,
                                ReferenceCheck& ref) {
  const auto computed = [&] {
    ShardReference runs = run_reference(model, spec, hooks);
    runs.touches_at_end = runs.fine_finished && cloth_touches(model, runs.fine);
    return runs;
  };
  const ReferenceCache cache(spec.reference_cache);
  if (!cache.enabled()) return computed();
  const std::string key = reference_key(model, spec);
  ref.cache_file = cache.path_of(key);
  if (const std::optional<std::string> payload = cache.load(key)) {
    std::istringstream in(*payload);
    std::string tag, cpu[2];
    RunTotals totals[2];
    int touches = 0;
    if (in >> tag >> totals[0].steps >> totals[0].force_evals >> cpu[0] >> totals[1].steps >> totals[1].force_evals >>
        cpu[1] >> touches && tag == "totals") {
      try {
        ShardReference runs = read_reference(payload->substr(payload->find('\n') + 1));
        for (int k = 0; k < 2; ++k) totals[k].cpu_seconds = std::strtod(cpu[k].c_str(), nullptr);
        runs.coarse_totals = totals[0], runs.fine_totals = totals[1];
        runs.touches_at_end = touches == 1;
        ref.cache = "reused";
        return runs;
      } catch (const StudyError&) {
        // checked, yet not a reference (another build's layout): computed again, stored over it
      }
    }
  }
  ShardReference runs = computed();
  if (runs.stopped || !runs.finished) {
    ref.cache = runs.stopped ? "not stored: stopped before its end" : "not stored: it did not reach T";
    return runs;
  }
  char totals[160];
  std::snprintf(totals, sizeof totals, "totals %" PRId64 " %" PRId64 " %a %" PRId64 " %" PRId64 " %a %d\n",
                runs.coarse_totals.steps, runs.coarse_totals.force_evals, runs.coarse_totals.cpu_seconds,
                runs.fine_totals.steps, runs.fine_totals.force_evals, runs.fine_totals.cpu_seconds,
                runs.touches_at_end ? 1 : 0);
  std::string why;
  ref.cache = cache.store(key, totals + reference_text(runs, model.num_particles), &why) ? "stored" : "not stored: " + why;
  return runs;
}

void judge_reference(const Model& model, const ShardReference& runs, double h_fine, WorkPrecisionResult& result) {
  ReferenceCheck& ref = result.reference;
  std::ostringstream why;
  why.precision(3);
  const std::string ref_name(integrator_name(ref.integrator));
  if (!ref.finished) {
    const bool coarse_failed = !runs.coarse_finished;
    const std::optional<Divergence>& bad = coarse_failed ? runs.coarse_divergence : runs.fine_divergence;
    const double h = coarse_failed ? 2 * h_fine : h_fine;
    if (bad)
      why << "the reference run (" << ref_name << " at dt = " << h << " s) diverged at t = " << bad->t << " s ("
          << bad->reason << ")";
    else
      why << "the reference run (" << ref_name << " at dt = " << h << " s) was stopped before T";
  } else {
    ref.change_rms = ref.over_time ? runs.change_rms_over_time : runs.change_rms;
    ref.change_max = ref.over_time ? runs.change_max_over_time : runs.change_max;
    // The barrier is a smooth force, not a correction once per step: no shortfall to blame on it.
    ref.contact_at_end = !smooth_scene(model) && runs.touches_at_end;
    ref.velocity_forces = model.air_drag > 0.0 ||
                          std::any_of(model.springs.kd.begin(), model.springs.kd.end(), [](double kd) { return kd > 0.0; });
    ref.unresolved = mark_unresolved(result.points, ref.change_rms, ref.margin);
    ref.smallest_error = smallest_resolved(result.points);
    // Points it cannot resolve fail it unless it is at round-off itself: then so are they, and
    // no reference in double precision could do better.
    ref.round_off = round_off_floor(model);
    if (ref.unresolved > 0 && ref.change_rms > ref.round_off) {
      why << "the reference is not converged: ";
      if (ref.adaptive)
        why << "tightening its tolerance (" << ref.tolerance << " -> " << ref.tolerance / kReferenceTightening << ")";
      else
        why << "halving its step (" << ref_name << " at " << 2 * h_fine << " s -> " << h_fine << " s)";
      why << " moved the particles by " << ref.change_rms << " m RMS, more than " << ref.margin << " x the error of "
          << ref.unresolved << " point" << (ref.unresolved == 1 ? "" : "s") << " (unresolved)"
          << (ref.adaptive ? "; give a smaller --reference-tolerance or larger step sizes"
                           : "; use larger step sizes or a finer reference");
    }
  }
  ref.failure = why.str();
  ref.converged = ref.failure.empty();
}

}  // namespace

WorkPrecisionResult work_precision(const Model& model, const WorkPrecisionSpec& spec_in,
                                   const StudyHooks& hooks) {
  const WorkPrecisionSpec spec = checked(spec_in);
  const double h_coarse = spec.dts.front() / spec.reference_refinement;
  WorkPrecisionResult result;
  result.duration = spec.duration;
  const std::vector<WorkPrecisionPoint> planned = planned_points(spec);

  // Progress over both phases, each run weighed by its cost estimate (the reference's two
  // first: they are what the points wait for).
  const double reference_cost = cost_estimate(spec.reference_integrator, spec.duration, h_coarse) +
                                cost_estimate(spec.reference_integrator, spec.duration, 0.5 * h_coarse);
  double points_cost = 0.0;
  for (const WorkPrecisionPoint& p : planned) points_cost += point_cost(p, spec.duration);
  const long runs_total = static_cast<long>(planned.size()) + 2;
  const ShardReference runs = cached_reference(model, spec, hooks, result.reference);
  StudyHooks point_hooks = hooks;
  if (hooks.progress)
    point_hooks.progress = [&](const StudyProgress& p) {
      hooks.progress(StudyProgress{p.done + 2, runs_total, p.work_done + reference_cost, reference_cost + points_cost});
    };
  if (!runs.stopped) {
    if (hooks.progress) hooks.progress(StudyProgress{2, runs_total, reference_cost, reference_cost + points_cost});
    std::vector<std::size_t> items(planned.size());
    for (std::size_t k = 0; k < items.size(); ++k) items[k] = k;
    result.points = run_points(model, spec, runs, items, point_hooks, {});
  }
  result.complete = !runs.stopped && result.points.size() == planned.size();

  ReferenceCheck& ref = result.reference;
  ref.integrator = spec.reference_integrator;
  ref.adaptive = uses_adaptive_reference(model, spec);
  ref.tolerance = ref.adaptive ? spec.reference_tolerance : 0.0;
  ref.dt = ref.adaptive ? 0.0 : 0.5 * h_coarse;
  ref.margin = spec.reference_margin;
  ref.over_time = spec.error_over_time;
  ref.samples = static_cast<int>(sample_times(spec).size());
  ref.finished = runs.finished;
  ref.steps = runs.coarse_totals.steps + runs.fine_totals.steps;
  ref.force_evals = runs.coarse_totals.force_evals + runs.fine_totals.force_evals;
  ref.cpu_seconds = runs.coarse_totals.cpu_seconds + runs.fine_totals.cpu_seconds;
  if (runs.fine_finished) result.reference_x = runs.fine.x.leftCols(model.num_particles);
  ref.smallest_error = kNaN;
  judge_reference(model, runs, 0.5 * h_coarse, result);
  return result;
}

bool uses_adaptive_reference(const Model& model, const WorkPrecisionSpec& spec) {
  return spec.adaptive_reference && smooth_scene(model);
}

StudyRun reference_run(const Model& model, const WorkPrecisionSpec& spec, bool finer, const std::function<bool()>& stop,
                       const Sampling& sampling) {
  if (uses_adaptive_reference(model, spec))
    return adaptive_run_to(model, finer ? spec.reference_tolerance / kReferenceTightening : spec.reference_tolerance,
                           spec.duration, stop, sampling);
  const double h_coarse = spec.dts.front() / spec.reference_refinement;
  return run_to(model, spec.reference_integrator, finer ? 0.5 * h_coarse : h_coarse, spec.duration, stop, sampling);
}

int mark_unresolved(std::vector<WorkPrecisionPoint>& points, double reference_error, double margin) {
  int count = 0;
  for (WorkPrecisionPoint& p : points) {
    p.unresolved = p.finished && p.rms_error * margin < reference_error;
    count += p.unresolved ? 1 : 0;
  }
  return count;
}

double state_scale(const Model& model) {
  double scale = 0.0;
  for (int b = 0; b < model.initial_x.cols(); ++b) scale = std::max(scale, model.initial_x.col(b).cwiseAbs().maxCoeff());
  for (double r : model.sphere_radius) scale = std::max(scale, r);
  return scale;
}

double round_off_floor(const Model& model) { return kRoundOffRelative * state_scale(model); }

int nominal_order(IntegratorKind kind) { return integrator_info(kind).order; }

namespace {

std::string metres(double m) {
  std::ostringstream out;
  out.precision(2);
  out << m << " m";
  return out.str();
}

// The finished points `take` accepts at the common steps with an error to fit.
template <class Take>
std::vector<const WorkPrecisionPoint*> fitted_points(const WorkPrecisionResult& r, Take take) {
  std::vector<const WorkPrecisionPoint*> out;
  for (const WorkPrecisionPoint& p : r.points)
    if (take(p) && !p.frame_step && p.finished && p.rms_error > 0.0) out.push_back(&p);
  return out;
}

std::vector<std::string> shortfall(const WorkPrecisionResult& r, double order, IntegratorKind kind,
                                   const std::vector<const WorkPrecisionPoint*>& fitted);

}  // namespace

std::vector<std::string> order_shortfall(const WorkPrecisionResult& r, IntegratorKind kind) {
  const auto take = [&](const WorkPrecisionPoint& p) { return p.integrator == kind; };
  return shortfall(r, convergence_order(r.points, kind), kind, fitted_points(r, take));
}

std::vector<std::string> lane_order_shortfall(const WorkPrecisionResult& r, std::size_t lane, IntegratorKind kind) {
  const auto take = [&](const WorkPrecisionPoint& p) { return p.lane == lane; };
  return shortfall(r, lane_convergence_order(r.points, lane), kind, fitted_points(r, take));
}

namespace {

std::vector<std::string> shortfall(const WorkPrecisionResult& r, double order, IntegratorKind kind,
                                   const std::vector<const WorkPrecisionPoint*>& fitted) {
  // An adaptive lane's slope is against its tolerance, not its step: no order to fall short of.
  if (std::isnan(order) || order >= 0.5 * nominal_order(kind) || integrator_info(kind).adaptive) return {};
  double smallest = INFINITY, largest_dt = 0.0;
  for (const WorkPrecisionPoint* p : fitted) smallest = std::min(smallest, p->rms_error), largest_dt = std::max(largest_dt, p->dt);
  const ReferenceCheck& ref = r.reference;
  std::vector<std::string> why;
  const int damped = integrator_info(kind).velocity_force_order;
  if (ref.velocity_forces && damped > 0 && order >= 0.75 * damped)
    why.push_back("velocity-dependent forces: the scene's dampers or drag make " + std::string(integrator_name(kind)) +
                  "'s Verlet kicks unsymmetric, and its composition keeps order " + std::to_string(damped) +
                  " only (docs/integrators.md, \"Verlet and Yoshida\")");
  if (ref.finished && (!ref.converged || smallest < 30.0 * ref.change_rms))
    why.push_back("reference not converged: its own change on halving (" + metres(ref.change_rms) +
                  " RMS) is within 30x of these errors (smallest " + metres(smallest) +
                  "); try --reference-refinement 16 or larger --dts");
  if (ref.contact_at_end)
    why.push_back("contact-limited: the cloth touches a sphere or the ground at T, and a contact is resolved once "
                  "per step, a non-smooth correction no method's order survives (errors level off near " +
                  metres(smallest) + "); try a --duration that ends before the first contact");
  if (smallest < ref.round_off)
    why.push_back("round-off: the smallest errors (" + metres(smallest) + ") reach double precision; drop the smallest --dts");
  const double steps = r.duration / largest_dt;
  if (steps < 20.0) {
    std::ostringstream t;
    t.precision(3);
    t << "T too short: T = " << r.duration << " s holds only " << steps << " of the largest steps (" << largest_dt
      << " s), so start-up, not the asymptotic error, is measured; try a longer --duration";
    why.push_back(t.str());
  }
  if (why.empty())
    why.push_back("the steps may lie outside the asymptotic range (w h not small for the stiffest springs); "
                  "try smaller --dts");
  return why;
}

}  // namespace

}  // namespace clothsim::analysis
