#include "work_precision.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

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

std::vector<WorkPrecisionPoint> planned_points(const WorkPrecisionSpec& spec) {
  std::vector<WorkPrecisionPoint> points;
  for (IntegratorKind kind : spec.integrators)
    for (double dt : steps_of(spec, kind)) {
      WorkPrecisionPoint p;
      p.integrator = kind;
      p.dt = dt;
      p.frame_step = std::find(spec.dts.begin(), spec.dts.end(), dt) == spec.dts.end();
      p.rms_error = p.max_error = kNaN;
      points.push_back(p);
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
  p.wall_seconds = run.totals.sim_seconds;
  p.cpu_seconds = run.totals.cpu_seconds;
  if (p.finished && reference) {
    const PositionError e = position_error(model, run.final_state.x, reference->x, reference->inv_mass);
    p.rms_error = e.rms;
    p.max_error = e.max;
  }
  return p;
}

// The steps `kind` runs: the common list, and for implicit Euler the frame-rate steps too.
std::vector<double> steps_of(const WorkPrecisionSpec& spec, IntegratorKind kind) {
  std::vector<double> dts = spec.dts;
  if (kind == IntegratorKind::ImplicitEuler) {
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
  for (std::size_t i = 0; i < spec.integrators.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (spec.integrators[i] == spec.integrators[j])
        throw StudyError("integrator " + std::string(integrator_name(spec.integrators[i])) + " is listed twice");
  if (spec.reference_refinement < 1) throw StudyError("the reference refinement must be >= 1");
  if (!(spec.reference_margin > 0.0)) throw StudyError("the reference margin must be > 0");
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

double convergence_order(const std::vector<WorkPrecisionPoint>& points, IntegratorKind kind) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (const WorkPrecisionPoint& p : points) {
    if (p.integrator != kind || p.frame_step || !p.finished || !(p.rms_error > 0.0)) continue;
    const double x = std::log(p.dt), y = std::log(p.rms_error);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
    ++n;
  }
  if (n < 2) return kNaN;
  const double denom = n * sxx - sx * sx;
  return denom != 0.0 ? (n * sxy - sx * sy) / denom : kNaN;
}

WorkPrecisionResult work_precision(const Model& model, const WorkPrecisionSpec& spec_in,
                                   const StudyHooks& hooks) {
  const WorkPrecisionSpec spec = checked(spec_in);
  const double T = spec.duration;
  const double h_coarse = spec.dts.front() / spec.reference_refinement;
  const double h_fine = 0.5 * h_coarse;

  // Task list: the two reference runs, then every (integrator, dt).
  struct Task {
    IntegratorKind kind;
    double dt;
    int point;  // index into result.points, or -1 / -2 for the coarse / fine reference
  };
  std::vector<Task> tasks{{spec.reference_integrator, h_coarse, -1}, {spec.reference_integrator, h_fine, -2}};
  WorkPrecisionResult result;
  result.duration = T;
  result.points = planned_points(spec);
  for (std::size_t k = 0; k < result.points.size(); ++k)
    tasks.push_back({result.points[k].integrator, result.points[k].dt, static_cast<int>(k)});
  std::stable_sort(tasks.begin(), tasks.end(), [&](const Task& a, const Task& b) {
    return cost_estimate(a.kind, T, a.dt) > cost_estimate(b.kind, T, b.dt);
  });

  std::vector<StudyRun> runs(result.points.size());
  std::vector<bool> ran(result.points.size(), false);
  StudyRun coarse, fine;
  std::mutex mutex;
  long done = 0;
  const long total = static_cast<long>(tasks.size());
  parallel_for(tasks.size(), spec.jobs, [&](std::size_t i) {
    const Task& task = tasks[i];
    StudyRun run = run_to(model, task.kind, task.dt, T, hooks.stop);
    std::lock_guard<std::mutex> lock(mutex);
    if (run.stopped) return;  // incomplete: neither a result nor a divergence
    if (task.point == -1) coarse = std::move(run);
    else if (task.point == -2) fine = std::move(run);
    else runs[task.point] = std::move(run), ran[task.point] = true;
    ++done;
    if (hooks.progress) hooks.progress(done, total);
  }, hooks.stop);

  // Errors against the finer reference, once both references are in.
  ReferenceCheck& ref = result.reference;
  ref.integrator = spec.reference_integrator;
  ref.dt = h_fine;
  ref.margin = spec.reference_margin;
  ref.finished = coarse.finished && fine.finished;
  if (fine.finished) result.reference_x = fine.final_state.x.leftCols(model.num_particles);
  std::vector<WorkPrecisionPoint> kept;
  ref.smallest_error = kNaN;
  for (std::size_t k = 0; k < result.points.size(); ++k) {
    if (!ran[k]) {
      result.complete = false;
      continue;
    }
    WorkPrecisionPoint p = measured_point(result.points[k], runs[k], model, fine.finished ? &fine.final_state : nullptr);
    if (p.finished && fine.finished && !(ref.smallest_error <= p.rms_error)) ref.smallest_error = p.rms_error;
    kept.push_back(std::move(p));
  }
  result.points = std::move(kept);

  std::ostringstream why;
  why.precision(3);
  const std::string ref_name(integrator_name(ref.integrator));
  if (!ref.finished) {
    const StudyRun& bad = !coarse.finished ? coarse : fine;
    const double h = !coarse.finished ? h_coarse : h_fine;
    if (bad.divergence)
      why << "the reference run (" << ref_name << " at dt = " << h << " s) diverged at t = "
          << bad.divergence->t << " s (" << bad.divergence->reason << ")";
    else
      why << "the reference run (" << ref_name << " at dt = " << h << " s) was stopped before T";
  } else {
    const PositionError change = position_error(model, coarse.final_state.x, fine.final_state.x,
                                                fine.final_state.inv_mass);
    ref.change_rms = change.rms;
    ref.change_max = change.max;
    // No finished point: nothing reported to compare with, so nothing the reference could spoil.
    const bool resolves = std::isnan(ref.smallest_error) || ref.change_rms <= ref.margin * ref.smallest_error;
    if (!resolves)
      why << "the reference is not converged: halving its step (" << ref_name << " at " << 2 * h_fine
          << " s -> " << h_fine << " s) moved the particles by " << ref.change_rms
          << " m RMS, more than " << ref.margin << " x the smallest error reported ("
          << ref.smallest_error << " m); use larger step sizes or a finer reference";
  }
  ref.failure = why.str();
  ref.converged = ref.failure.empty();
  return result;
}

}  // namespace clothsim::analysis
