#include "budget_study.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <numeric>

#include "reference.h"
#include "task_pool.h"
#include "work_precision.h"

namespace clothsim::analysis {
// Named, as well as file-local: a unity build joins this file's helpers with its neighbours'.
namespace budget_parts {
namespace {

constexpr double kUnmeasured = std::numeric_limits<double>::quiet_NaN();

// The served reference at every frame 0 .. T F: what each point is measured against.
struct ReferenceFrames {
  std::vector<Eigen::Matrix3Xd> x;     // (3 x B) per frame
  std::vector<Eigen::VectorXd> free;   // (B) inverse masses per frame (pins change at events)
};

double frame_time(const BudgetSpec& spec, int j) { return j / spec.fps; }

std::string g(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

void keep(ReferenceFrames& frames, const State& s) {
  frames.x.push_back(s.x);
  frames.free.push_back(s.inv_mass);
}

// The served solve's largest strain along the frames.
struct Along {
  double strain = 0.0;
  void see(const Model& model, const State& s) { strain = std::max(strain, max_strain(model, s)); }
};

// Whether an immovable body moves before T (external_work at the start, or a keyframe before T
// that sets a velocity): then something does work on the cloth, and energy lost is not dissipation.
bool colliders_move(const Model& model, const State& start, double T) {
  if (external_work(model, start)) return true;
  for (const TimedAction& a : model.timeline)
    if (a.kind == TimedAction::Kind::SetVelocity && a.t < T * (1 - 1e-9) && a.velocity.squaredNorm() > 0.0) return true;
  return false;
}

void finish_reference(const Model& model, const BudgetSpec& spec, const State& start, const State& end,
                      const Along& along, BudgetResult& r) {
  BudgetReference& ref = r.reference;
  ref.max_strain = along.strain;
  ref.energy_lost_per_second = (compute_energies(model, start).total() - compute_energies(model, end).total()) / spec.duration;
  r.colliders_move = colliders_move(model, start, spec.duration);
}

// The adaptive pair (compare's), advanced frame by frame: the served one's frames kept, twice its
// distance to the tighter check its error.
ReferenceFrames adaptive_reference(const Model& model, const BudgetSpec& spec, const StudyHooks& hooks, BudgetResult& r) {
  BudgetReference& ref = r.reference;
  ref.adaptive = true;
  ref.tolerance = spec.reference_tolerance;
  AdaptiveReference solve(model, spec.reference_tolerance);
  if (hooks.stop) solve.set_stop_check(hooks.stop);
  ReferenceFrames frames;
  const State start = solve.state();
  Along along;
  keep(frames, start);
  for (int j = 1; j <= r.frames; ++j) {
    if (!solve.advance_to(frame_time(spec, j))) break;
    keep(frames, solve.state());
    along.see(model, solve.state());
  }
  const RunTotals totals = solve.totals();
  ref.cpu_seconds = totals.cpu_seconds, ref.steps = totals.steps, ref.force_evals = totals.force_evals;
  ref.estimated_error = solve.estimated_error();
  ref.finished = static_cast<int>(frames.x.size()) == r.frames + 1;
  if (solve.stopped()) r.complete = false, ref.failure = "stopped";
  else if (solve.diverged())
    ref.failure = "the adaptive reference diverged at t = " + g(solve.divergence()->t) + " s (" +
                  solve.divergence()->reason + ")";
  if (ref.finished) finish_reference(model, spec, start, solve.state(), along, r);
  return frames;
}

// RK4 at h (served) and at 2 h (its check), on two threads, each keeping its frames.
ReferenceFrames rk4_reference(const Model& model, const BudgetSpec& spec, const StudyHooks& hooks, BudgetResult& r) {
  BudgetReference& ref = r.reference;
  ref.dt = spec.reference_dt;
  ReferenceFrames frames[2];
  RunTotals totals[2];
  std::optional<Divergence> divergence[2];
  bool stopped[2] = {false, false};
  Along along;
  State start, end;
  parallel_for(2, 2, [&](std::size_t i) {
    Run run(model, kReferenceIntegrator, i == 0 ? spec.reference_dt : 2.0 * spec.reference_dt);
    if (hooks.stop) run.set_stop_check(hooks.stop);
    keep(frames[i], run.state());
    if (i == 0) start = run.state();
    for (int j = 1; j <= r.frames; ++j) {
      if (!run.advance_to(frame_time(spec, j)) || run.stopped()) break;
      keep(frames[i], run.state());
      if (i == 0) along.see(model, run.state());
    }
    totals[i] = run.totals(), divergence[i] = run.divergence(), stopped[i] = run.stopped();
    if (i == 0) end = run.state();
  });
  ref.cpu_seconds = totals[0].cpu_seconds + totals[1].cpu_seconds;
  ref.steps = totals[0].steps + totals[1].steps;
  ref.force_evals = totals[0].force_evals + totals[1].force_evals;
  const auto whole = [&](int i) { return static_cast<int>(frames[i].x.size()) == r.frames + 1; };
  ref.finished = whole(0) && !stopped[0];
  if (stopped[0] || stopped[1]) r.complete = false, ref.failure = "stopped";
  else if (divergence[0])
    ref.failure = "the reference (rk4 at dt = " + g(spec.reference_dt) + " s) diverged at t = " +
                  g(divergence[0]->t) + " s (" + divergence[0]->reason + ")";
  ref.estimated_error = kUnmeasured;  // a check that failed gives no estimate
  if (ref.finished && whole(1) && !stopped[1]) {
    ref.estimated_error = 0.0;
    for (int j = 0; j <= r.frames; ++j)
      ref.estimated_error = std::max(ref.estimated_error,
                                     position_error(model, frames[1].x[j], frames[0].x[j], frames[0].free[j]).max);
  }
  if (ref.finished) finish_reference(model, spec, start, end, along, r);
  return std::move(frames[0]);
}

// One split run frame by frame, each frame measured against the reference (outside the run's
// CPU time: Run counts only its steps). `stopped` when hooks.stop ended it before T.
BudgetPoint run_point(const Model& model, const MethodSettings& settings, BudgetPoint p, const BudgetSpec& spec,
                      const ReferenceFrames& ref, const std::function<bool()>& stop, bool& stopped) {
  Run run(model, p.kind, p.dt, settings);
  if (stop) run.set_stop_check(stop);
  const double start_energy = compute_energies(model, run.state()).total();
  const int frames = static_cast<int>(ref.x.size()) - 1;
  for (int j = 1; j <= frames; ++j) {
    const bool live = run.advance_to(frame_time(spec, j));
    if (run.stopped()) {
      stopped = true;
      return p;
    }
    if (!live) break;
    const double e = position_error(model, run.state().x, ref.x[j], ref.free[j]).max;
    if (!(e <= p.max_error)) p.max_error = e, p.max_error_t = run.state().t;
    p.final_error = e;
    ++p.frames;
  }
  p.totals = run.totals();
  p.diverged = run.diverged();
  p.finished = !p.diverged;
  if (p.diverged) p.diverged_at = run.divergence()->t, p.reason = run.divergence()->reason;
  p.max_strain = p.totals.max_strain;
  if (p.finished) {
    p.max_strain = std::max(p.max_strain, max_strain(model, run.state()));
    p.energy_lost_per_second = (start_energy - compute_energies(model, run.state()).total()) / spec.duration;
  } else {
    p.max_error = p.max_error_t = p.final_error = p.energy_lost_per_second = kUnmeasured;
  }
  return p;
}

// Rough cost of a point in spring passes, for the schedule only (dearest first).
double point_cost(const BudgetSpec& spec, const BudgetPoint& p) {
  const double per_iteration = integrator_info(p.kind).iterations == IterationControl::Newton
                                   ? 8.0  // a Newton iteration: assembly and a few CG rounds
                                   : std::max(1.0, integrator_info(p.kind).passes_per_iteration);
  return spec.fps * spec.duration * (spec.budget * per_iteration + p.substeps);  // + a pass a step
}

std::string plural(int n, const char* word) { return std::to_string(n) + " " + word + (n == 1 ? "" : "s"); }

std::string length_text(double m) {
  char text[32];  // 0.1 mm .. 0.1 m in mm, as a drape's errors read
  if (m >= 1e-4 && m < 0.1) std::snprintf(text, sizeof text, "%.3g mm", m * 1e3);
  else std::snprintf(text, sizeof text, "%.3g m", m);
  return text;
}

std::string error_text(const BudgetPoint& p, const BudgetReference& ref, double margin) {
  if (p.diverged) {
    char text[64];
    std::snprintf(text, sizeof text, "DIVERGED at t = %.3g s", p.diverged_at);
    return text;
  }
  const std::string e = p.unresolved ? "under " + length_text(ref.estimated_error / margin) : length_text(p.max_error);
  return p.wrong() ? e + " (WRONG)" : e;
}

std::string iteration_word(IntegratorKind kind) {
  return integrator_info(kind).iterations == IterationControl::Newton ? "Newton iteration" : "iteration";
}

}  // namespace
}  // namespace budget_parts
using namespace budget_parts;

std::vector<int> divisors(int n) {
  std::vector<int> out;
  for (int s = 1; s <= n; ++s)
    if (n % s == 0) out.push_back(s);
  return out;
}

std::string solver_name(const BudgetSpec& spec, std::size_t i) {
  return i < spec.solver_names.size() ? spec.solver_names[i] : std::string(integrator_name(spec.solvers[i]));
}

std::vector<BudgetPoint> budget_points(const BudgetSpec& spec) {
  std::vector<BudgetPoint> points;
  for (std::size_t i = 0; i < spec.solvers.size(); ++i)
    for (int s : divisors(spec.budget)) {
      BudgetPoint p;
      p.solver = i;
      p.kind = spec.solvers[i];
      p.substeps = s;
      p.iterations = spec.budget / s;
      p.dt = 1.0 / (spec.fps * s);
      p.max_error = p.max_error_t = p.final_error = p.energy_lost_per_second = kUnmeasured;
      points.push_back(p);
    }
  return points;
}

BudgetSpec checked(BudgetSpec spec) {
  if (spec.budget < 1 || spec.budget > kMaxSolverIterations)
    throw StudyError("the budget must be a whole number from 1 to " + std::to_string(kMaxSolverIterations) +
                     " iterations a frame, got " + std::to_string(spec.budget));
  if (spec.solvers.empty()) throw StudyError("no solver to split the budget of");
  for (IntegratorKind k : spec.solvers)
    if (integrator_info(k).iterations == IterationControl::None)
      throw StudyError(std::string(integrator_name(k)) + " takes no iterations: a budget splits an iterative "
                       "solver's (xpbd, vbd, projective_dynamics, implicit_euler's Newton cap)");
  if (!spec.solver_names.empty() && spec.solver_names.size() != spec.solvers.size())
    throw StudyError("one name per solver");
  if (!(spec.fps > 0.0) || !std::isfinite(spec.fps)) throw StudyError("the frame rate must be a number > 0");
  const double frames = spec.duration * spec.fps;
  if (!(spec.duration > 0.0) || !std::isfinite(spec.duration) || std::round(frames) < 1.0 ||
      std::abs(frames - std::round(frames)) > 1e-9 * std::round(frames)) {
    char msg[160];
    std::snprintf(msg, sizeof msg, "T = %g s is not a whole number of frames at %g frames/s", spec.duration, spec.fps);
    throw StudyError(msg);
  }
  if (spec.reference_dt < 0.0 || spec.reference_dt > 1.0 / (spec.fps * spec.budget) * (1 + 1e-9))
    throw StudyError("the reference step must be > 0 and at most the smallest step, 1 / (F N)");
  if (!(spec.reference_tolerance > 0.0)) throw StudyError("the reference tolerance must be > 0");
  return spec;
}

BudgetResult budget_study(const Model& model, const BudgetSpec& spec_in, const StudyHooks& hooks) {
  BudgetResult r;
  r.spec = checked(spec_in);
  const BudgetSpec& spec = r.spec;
  r.frames = static_cast<int>(std::round(spec.duration * spec.fps));
  const bool adaptive = smooth_scene(model);
  if (!adaptive && !(spec.reference_dt > 0.0))
    throw StudyError("a scene with projected contacts needs the RK4 reference's step (reference_dt)");
  const std::vector<BudgetPoint> planned = budget_points(spec);
  StudyProgress progress{0, static_cast<long>(planned.size()) + 1};
  const ReferenceFrames ref = adaptive ? adaptive_reference(model, spec, hooks, r) : rk4_reference(model, spec, hooks, r);
  if (!r.reference.finished) {  // nothing to measure against
    r.complete = r.complete && !(hooks.stop && hooks.stop());
    return r;
  }
  ++progress.done;
  if (hooks.progress) hooks.progress(progress);

  std::vector<std::size_t> order(planned.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return point_cost(spec, planned[a]) > point_cost(spec, planned[b]);
  });
  std::vector<BudgetPoint> done(planned.size());
  std::vector<bool> ran(planned.size(), false);
  std::mutex mutex;
  parallel_for(order.size(), spec.jobs, [&](std::size_t n) {
    const std::size_t i = order[n];
    const BudgetPoint& p = planned[i];
    MethodSettings settings = model.method_defaults();
    if (spec.solver_settings) {
      settings = spec.solver_settings(model, p.solver, p.iterations);
    } else if (int* count = iteration_count(settings, p.kind)) {
      *count = p.iterations;
    }
    bool stopped = false;
    BudgetPoint measured = run_point(model, settings, p, spec, ref, hooks.stop, stopped);
    std::lock_guard<std::mutex> lock(mutex);
    if (stopped) return;
    done[i] = std::move(measured);
    ran[i] = true;
    ++progress.done;
    if (hooks.progress) hooks.progress(progress);
  }, hooks.stop);

  for (std::size_t i = 0; i < planned.size(); ++i) {
    if (!ran[i]) {
      r.complete = false;
      continue;
    }
    BudgetPoint& p = done[i];
    p.unresolved = p.finished && p.max_error * spec.reference_margin < r.reference.estimated_error;
    r.points.push_back(std::move(p));
  }
  return r;
}

std::string budget_status(const BudgetPoint& p, double margin) {
  char status[200];
  const bool capped = integrator_info(p.kind).iterations == IterationControl::Newton;
  if (p.diverged) std::snprintf(status, sizeof status, "DIVERGED at t = %.4g s: %s", p.diverged_at, p.reason.c_str());
  else if (p.totals.unconverged_steps > 0 && !capped)
    std::snprintf(status, sizeof status, "NOT CONVERGED: %" PRId64 " of %" PRId64 " steps", p.totals.unconverged_steps,
                  p.totals.steps);
  else if (p.wrong())
    std::snprintf(status, sizeof status, "WRONG at t = %.4g s: %s", p.totals.wrong->t, p.totals.wrong->reason.c_str());
  else if (p.unresolved) std::snprintf(status, sizeof status, "unresolved: under %g x the reference's error", 1.0 / margin);
  else if (p.totals.unconverged_steps > 0)  // a Newton cap stops steps short on purpose (Lane::newton_capped)
    std::snprintf(status, sizeof status, "ok (Newton capped at %d: residual up to %.2g)", p.iterations,
                  p.totals.max_residual);
  else std::snprintf(status, sizeof status, "ok");
  return status;
}

BudgetVerdict budget_verdict(const BudgetResult& r, std::size_t solver) {
  BudgetVerdict v;
  const double margin = r.spec.reference_margin;
  int first = -1, last = -1;  // the grid's ends: 1 x N and N x 1
  bool resolved = false;      // some candidate's error is a number
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const BudgetPoint& p = r.points[i];
    if (p.solver != solver) continue;
    if (p.substeps == 1) first = static_cast<int>(i);
    if (p.substeps == r.spec.budget) last = static_cast<int>(i);
    if (!p.finished || p.wrong()) continue;
    resolved = resolved || !p.unresolved;
    const auto better = [&](const BudgetPoint& a, const BudgetPoint& b) {  // a beats b
      if (a.unresolved != b.unresolved) return a.unresolved;  // under the reference's reach: below every number
      if (a.unresolved) return a.totals.cpu_seconds < b.totals.cpu_seconds;
      return a.max_error < b.max_error;
    };
    if (v.winner < 0 || better(p, r.points[v.winner])) v.winner = static_cast<int>(i);
  }
  const std::string head = solver_name(r.spec, solver) + " at N = " + std::to_string(r.spec.budget) + ": ";
  if (v.winner < 0) {
    v.text = head + "no split finished without diverging or reading WRONG";
    return v;
  }
  const auto split = [](const BudgetPoint& p) { return std::to_string(p.substeps) + " x " + std::to_string(p.iterations); };
  char tail[160];
  if (!resolved) {  // the reference cannot rank them: say so, and what strain and CPU say
    v.winner = -1;
    std::string text = head + "no winner by error: every split that finished is under " +
                       length_text(r.reference.estimated_error / margin) + " (10x the reference's own error)";
    if (first >= 0 && last >= 0 && first != last && r.points[first].finished && r.points[last].finished) {
      std::snprintf(tail, sizeof tail, "; strain %.3g for %s against %.3g for %s (reference %.3g)",
                    r.points[last].max_strain, split(r.points[last]).c_str(), r.points[first].max_strain,
                    split(r.points[first]).c_str(), r.reference.max_strain);
      text += tail;
    }
    v.text = text;
    return v;
  }
  const BudgetPoint& w = r.points[v.winner];
  v.against = v.winner == first ? last : first;
  if (v.against == v.winner) v.against = -1;  // N = 1: one split
  std::string text = head + plural(w.substeps, "substep") + " x " + plural(w.iterations, iteration_word(w.kind).c_str()) +
                     " wins: error " + error_text(w, r.reference, margin);
  if (v.against < 0) {
    std::snprintf(tail, sizeof tail, ", strain %.3g (the only split; reference %.3g)", w.max_strain, r.reference.max_strain);
    v.text = text + tail;
    return v;
  }
  const BudgetPoint& a = r.points[v.against];
  text += " against " + error_text(a, r.reference, margin) + " for " + split(a);
  if (v.winner != first && v.winner != last && last >= 0)  // an inner split: both ends
    text += " and " + error_text(r.points[last], r.reference, margin) + " for " + split(r.points[last]);
  if (a.finished) {
    std::snprintf(tail, sizeof tail, ", strain %.3g against %.3g (reference %.3g), CPU %.2gx", w.max_strain,
                  a.max_strain, r.reference.max_strain,
                  a.totals.cpu_seconds > 0 ? w.totals.cpu_seconds / a.totals.cpu_seconds : kUnmeasured);
    text += tail;
  }
  v.text = text;
  return v;
}

}  // namespace clothsim::analysis
