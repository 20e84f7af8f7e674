#include "step_matching.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "clip/common/cli_common.h"
#include "core/run/simulation.h"
#include "core/run/work_units.h"
#include "scene/echo.h"

namespace clothsim::clip {

namespace {

constexpr double kPilotWindow = 2.0;    // s of the clip a search pilot runs (the fall and the contact)
constexpr double kFirstPilotWindow = 0.1;  // s: the pilot at the scene's step, only to rank the lanes
// What a signal during the pilots and trial runs says (nothing is written yet then).
constexpr const char* kPlanning = "while choosing the lanes' steps";
constexpr double kCostTolerance = 0.05; // a pilot within 5 % of the target cost is taken
constexpr int kMaxPilots = 6;
// An adaptive pair's matched tolerance stays inside these (rtol = atol).
constexpr double kLoosestTolerance = 1e-2, kTightestTolerance = 1e-12;
constexpr int kToleranceBisections = 4;  // the last passing tolerance within 10^(1/16) of the loosest

std::string format(const char* fmt, double a, double b = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

// A step above a millisecond as a whole fraction of a second ("1/58"), else as it is.
void set_step(Lane& lane, double h, StepFrom from) {
  lane.step_from = from;
  if (h > 1e-3 && h < 1.0) {
    const double n = std::round(1.0 / h);
    lane.dt = 1.0 / n;
    lane.step_text = "1/" + number_text(n);
    return;
  }
  lane.dt = h;
  lane.step_text = step_string(h);
}

// Passes per step that do not depend on the step: the explicit family's force evaluations.
// Newton's work and an iterative solver's (its iterations, a factor per step size) are
// measured by pilot runs instead.
std::optional<double> fixed_work(const Lane& lane) {
  if (lane.fixed_point || integrator_info(lane.kind).iterations != IterationControl::None)
    return std::nullopt;
  return static_cast<double>(nominal_force_evals(lane.kind));
}

double cost_at(const Model& model, const Lane& lane, double h, double duration) {
  if (const auto w = fixed_work(lane)) return *w / h;
  return pilot_cost(model, lane, h, std::min(kFirstPilotWindow, duration));
}

// The step where `lane` costs `target` passes per simulated second: from (h0, c0), first as if
// its work per step did not change, then by a secant on log cost over log step between the
// pilots. Returns the step and the pilots run.
std::pair<double, int> step_for_cost(const Model& model, const Lane& lane, double h0, double c0, double target,
                                     double window) {
  double h = h0 * c0 / target, h_prev = 0.0, c_prev = 0.0;
  double best = h, best_gap = std::numeric_limits<double>::infinity();
  int pilots = 0;
  while (pilots < kMaxPilots) {
    const double c = pilot_cost(model, lane, h, window);
    ++pilots;
    const double gap = std::abs(std::log(c / target));
    if (gap < best_gap) best = h, best_gap = gap;
    if (gap <= kCostTolerance) break;
    double slope = -1.0;  // d log c / d log h with constant work per step
    if (h_prev > 0.0) slope = std::min(-0.05, std::log(c / c_prev) / std::log(h / h_prev));
    h_prev = h, c_prev = c;
    h = std::clamp(h * std::exp(std::log(target / c) / slope), h / 16.0, h * 16.0);
  }
  return {best, pilots};
}

// An adaptive pair whose tolerance is left to --match: neither :tol= nor :rtol= nor :atol=.
bool tolerance_free(const Lane& lane) {
  return integrator_info(lane.kind).adaptive && lane.rtol == 0.0 && lane.atol == 0.0;
}

// A matched tolerance to two figures: it labels a tile and a summary row ("dopri5:tol=3.7e-07").
double two_figures(double tol) { return std::stod(format("%.2g", tol)); }

Lane at_tolerance(const Lane& lane, double tol) {
  Lane out = lane;
  out.rtol = out.atol = tol;
  return out;
}

// The tolerance where the pair costs `target` passes per simulated second: from the scene's
// tolerance, a secant on log cost over log tolerance (about -1/(q+1) for a pair of order q).
std::pair<double, int> tolerance_for_cost(const Model& model, const Lane& lane, double target, double window) {
  double tol = model.adaptive.rtol, tol_prev = 0.0, c_prev = 0.0;
  double best = tol, best_gap = std::numeric_limits<double>::infinity();
  int pilots = 0;
  while (pilots < kMaxPilots) {
    const double c = pilot_cost(model, at_tolerance(lane, tol), lane.dt, window);
    ++pilots;
    const double gap = std::abs(std::log(c / target));
    if (gap < best_gap) best = tol, best_gap = gap;
    if (gap <= kCostTolerance) break;
    double slope = -1.0 / (integrator_info(lane.kind).order + 1.0);
    if (tol_prev > 0.0 && tol != tol_prev) slope = std::min(-0.02, std::log(c / c_prev) / std::log(tol / tol_prev));
    tol_prev = tol, c_prev = c;
    tol = std::clamp(tol * std::exp(std::log(target / c) / slope), kTightestTolerance, kLoosestTolerance);
    if (tol == tol_prev) break;  // at a bound: nothing further to try
  }
  return {best, pilots};
}

// (models[i]: the model lane i runs, its own under --vary)
std::vector<std::string> match_cost(const std::vector<const Model*>& models, std::vector<Lane>& lanes,
                                    const std::vector<bool>& free, const MatchClip& clip) {
  const double window = std::min(kPilotWindow, clip.duration);
  std::vector<double> cost(lanes.size(), std::numeric_limits<double>::infinity());
  std::size_t cheapest = lanes.size();
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    if (!free[i]) continue;
    cost[i] = cost_at(*models[i], lanes[i], clip.scene_dt, clip.duration);
    if (cheapest == lanes.size() || cost[i] < cost[cheapest]) cheapest = i;
  }
  std::vector<std::string> how(lanes.size(), "your step");
  if (cheapest == lanes.size()) return how;
  const double target = cost[cheapest];
  const std::string name = lanes[cheapest].name();
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    if (!free[i]) continue;
    if (i == cheapest) {
      how[i] = format("the scene's step; the cheapest there, %.3g spring passes per simulated s (sets the cost)", target);
      continue;
    }
    if (const auto w = fixed_work(lanes[i])) {
      set_step(lanes[i], *w / target, StepFrom::MatchedCost);
      how[i] = format("matched on cost: %.0f passes a step, %.3g per simulated s", *w, target) + ", as " + name;
      continue;
    }
    const auto [h, pilots] = step_for_cost(*models[i], lanes[i], clip.scene_dt, cost[i], target, window);
    set_step(lanes[i], h, StepFrom::MatchedCost);
    how[i] = format(pilots == 1 ? "matched on cost by %.0f pilot run over the clip's first %g s"
                                : "matched on cost by %.0f pilot runs over the clip's first %g s",
                    pilots, window) +
             format(" to %.3g spring passes per simulated s", target) + ", as " + name;
  }
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    if (!tolerance_free(lanes[i])) continue;
    const auto [tol, pilots] = tolerance_for_cost(*models[i], lanes[i], target, window);
    lanes[i] = at_tolerance(lanes[i], two_figures(tol));
    how[i] = format("its tolerance %.2g matched on cost by %.0f pilot runs", tol, pilots) +
             format(" over the clip's first %g s to %.3g spring passes per simulated s", window, target) + ", as " +
             name + " (an adaptive pair; its steps its own)";
  }
  return how;
}


// Steps a frame of the reference: 1 / (fps K) at most its step, landing on the frames.
long reference_steps_per_frame(const Lane& reference, double fps) {
  return std::max(1L, static_cast<long>(std::ceil(1.0 / (fps * reference.dt))));
}

// The reference's particle positions (3 x P) at every frame of the clip, from steps of
// 1 / (fps K) that land on the frames exactly; stops where the reference diverges.
std::vector<Eigen::Matrix3Xd> reference_frames(const Model& model, const Lane& reference, const MatchClip& clip) {
  Run run(model, reference.kind, error_reference(reference, clip.fps).dt, lane_settings(model, reference));
  run.set_stop_check(interrupted);
  std::vector<Eigen::Matrix3Xd> frames;
  const long last = static_cast<long>(std::floor(clip.duration * clip.fps + 1e-9));
  for (long k = 0; k <= last; ++k) {
    if (!run.advance_to(static_cast<double>(k) / clip.fps)) break;
    stop_if_interrupted(kPlanning);
    frames.push_back(run.state().x.leftCols(model.num_particles));
  }
  return frames;
}

// Whether `lane` at step h stays within `tolerance` of `frames` at every frame (stopping at the
// first that does not, or at divergence): a trial of either search below.
bool within(const Model& model, const Lane& lane, double h, const std::vector<Eigen::Matrix3Xd>& frames,
            double tolerance, double fps) {
  Run run(model, lane.kind, h, lane_settings(model, lane));
  run.set_stop_check(interrupted);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const bool reached = run.advance_to(static_cast<double>(f) / fps);
    stop_if_interrupted(kPlanning);
    if (!reached) return false;
    const double worst = (run.state().x.leftCols(model.num_particles) - frames[f]).colwise().norm().maxCoeff();
    if (!(worst <= tolerance)) return false;
  }
  return true;
}

// The smallest k (the largest step 1 / (fps k)) within tolerance: k doubled until a trial
// passes, then bisected between the last that failed and it. 0 when none does up to `cap`
// (the reference's own steps a frame: no finer step is measured by it).
std::pair<long, int> smallest_passing_k(const Model& model, const Lane& lane,
                                        const std::vector<Eigen::Matrix3Xd>& frames, double tolerance, double fps,
                                        long cap) {
  int trials = 0;
  const auto passes = [&](long k) {
    return ++trials, within(model, lane, 1.0 / (fps * static_cast<double>(k)), frames, tolerance, fps);
  };
  long bad = 0, good = 1;
  while (!passes(good)) {
    bad = good;
    if (good >= cap) return {0, trials};
    good = std::min(2 * good, cap);
  }
  while (good - bad > 1) {
    const long mid = bad + (good - bad) / 2;
    (passes(mid) ? good : bad) = mid;
  }
  return {good, trials};
}

// The loosest tolerance (rtol = atol) within `tolerance` metres: from `tolerance` itself (a
// pair's error is about its tolerance on a scene of unit size) tenfold looser while trials pass
// or tighter until one does, then bisected on log tolerance between the last that failed and
// the last that passed. 0 when none passes down to kTightestTolerance.
std::pair<double, int> loosest_passing_tolerance(const Model& model, const Lane& lane,
                                                 const std::vector<Eigen::Matrix3Xd>& frames, double tolerance,
                                                 double fps) {
  int trials = 0;
  const auto passes = [&](double tol) {
    return ++trials, within(model, at_tolerance(lane, tol), lane.dt, frames, tolerance, fps);
  };
  double good = 0.0, bad = 0.0, tol = two_figures(std::clamp(tolerance, kTightestTolerance, kLoosestTolerance));
  if (passes(tol)) {  // looser, tenfold, until a trial fails
    for (good = tol; bad == 0.0 && good < kLoosestTolerance;) {
      const double looser = std::min(10.0 * good, kLoosestTolerance);
      (passes(looser) ? good : bad) = looser;
    }
    if (bad == 0.0) return {good, trials};
  } else {  // tighter, tenfold, until a trial passes
    for (bad = tol; good == 0.0;) {
      if (bad <= kTightestTolerance) return {0.0, trials};
      const double tighter = std::max(bad / 10.0, kTightestTolerance);
      (passes(tighter) ? good : bad) = tighter;
    }
  }
  for (int i = 0; i < kToleranceBisections; ++i) {
    const double mid = two_figures(std::sqrt(good * bad));
    if (mid >= bad || mid <= good) break;  // two figures no longer split them
    (passes(mid) ? good : bad) = mid;
  }
  return {good, trials};
}

std::vector<std::string> match_error(const Model& model, std::vector<Lane>& lanes, const std::vector<bool>& free,
                                     double tolerance, const MatchClip& clip, const Lane& reference) {
  const std::vector<Eigen::Matrix3Xd> frames = reference_frames(model, reference, clip);
  std::vector<std::string> how(lanes.size(), "your step");
  const std::string against = " against " + reference.name() + " @ " + step_string(reference.dt) + " s";
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    if (!tolerance_free(lanes[i])) continue;
    const auto [tol, trials] = loosest_passing_tolerance(model, lanes[i], frames, tolerance, clip.fps);
    if (tol == 0.0) {
      how[i] = format("error %g m not reached at any tolerance down to %g", tolerance, kTightestTolerance) +
               format(", in %.0f trial runs: the scene's tolerance", trials) + against;
      continue;
    }
    lanes[i] = at_tolerance(lanes[i], tol);  // a trial's own tolerance, already two figures
    how[i] = format("its tolerance %.2g matched on error: the loosest within %g m at every frame", tol, tolerance) +
             format(", %.0f trial runs (tenfold steps, then bisection)", trials) + against + " (an adaptive pair)";
  }
  for (std::size_t i = 0; i < lanes.size(); ++i) {
    if (!free[i]) continue;
    const long cap = reference_steps_per_frame(reference, clip.fps);
    const auto [k, trials] = smallest_passing_k(model, lanes[i], frames, tolerance, clip.fps, cap);
    if (k == 0) {
      how[i] = format("error %g m not reached at any step down to the reference's, 1/(fps x %.0f)", tolerance,
                      static_cast<double>(cap)) +
               format(", in %.0f trial runs: the scene's step", trials) + against;
      continue;
    }
    set_step(lanes[i], 1.0 / (clip.fps * static_cast<double>(k)), StepFrom::MatchedError);
    lanes[i].step_text = "1/" + number_text(clip.fps * static_cast<double>(k));
    how[i] = format("matched on error: the largest step 1/(fps k) within %g m at every frame, %.0f trial runs "
                    "(doubling, then bisection)", tolerance, trials) + against;
  }
  return how;
}

}  // namespace

Lane error_reference(const Lane& reference, double fps) {
  Lane out = reference;
  const double K = static_cast<double>(reference_steps_per_frame(reference, fps));
  out.dt = 1.0 / (fps * K);
  out.step_text = "1/" + number_text(fps * K);
  return out;
}

MatchRequest parse_match(const std::vector<std::string>& words) {
  if (words.size() == 1 && words[0] == "cost") return {MatchKind::Cost, 0.0};
  if (words.size() == 1 && words[0] == "none") return {MatchKind::None, 0.0};
  if (!words.empty() && words[0] == "error") {
    if (words.size() != 2) throw UsageError("--match error needs a tolerance in metres: --match error 1e-3");
    const std::optional<double> tol = parse_number_or_fraction(words[1]);
    if (!tol || !(*tol > 0.0) || !std::isfinite(*tol))
      throw UsageError("--match error: tolerance must be a number > 0 (metres), got " + in_quotes(words[1]));
    return {MatchKind::Error, *tol};
  }
  std::string said;
  for (const std::string& w : words) said += (said.empty() ? "" : " ") + w;
  throw UsageError("--match: expected cost, error TOL or none, got " + in_quotes(said));
}

double pilot_cost(const Model& model, const Lane& lane, double h, double window) {
  Run run(model, lane.kind, h, lane_settings(model, lane));
  run.set_stop_check(interrupted);  // a pilot of a large sheet runs for minutes
  run.advance_to(window);
  stop_if_interrupted(kPlanning);
  const double t = run.divergence() ? std::max(run.divergence()->t, h) : std::max(run.state().t, h);
  return spring_passes(run.totals()) / t;
}

std::vector<std::string> match_steps(const Model& model, std::vector<Lane>& lanes,
                                     const MatchRequest& request, const MatchClip& clip, const Lane& reference,
                                     const std::vector<const Model*>& lane_models) {
  std::vector<bool> free, free_tolerance;  // the lanes given no step (@STEP, --dt) or no tolerance
  for (const Lane& l : lanes) free.push_back(l.free_step()), free_tolerance.push_back(tolerance_free(l));
  std::vector<const Model*> models = lane_models;
  if (models.empty()) models.assign(lanes.size(), &model);
  std::vector<std::string> how;
  switch (request.kind) {
    case MatchKind::Cost:
      how = match_cost(models, lanes, free, clip);
      break;
    case MatchKind::Error:
      how = match_error(model, lanes, free, request.tolerance, clip, reference);
      break;
    case MatchKind::None:
      for (std::size_t i = 0; i < lanes.size(); ++i)
        how.push_back(free[i] ? "the scene's step (--match none)" : "your step");
      break;
  }
  for (std::size_t i = 0; i < lanes.size(); ++i)  // an adaptive pair is never matched on a step
    if (integrator_info(lanes[i].kind).adaptive && !(free_tolerance[i] && request.kind != MatchKind::None && how[i] != "your step"))
      how[i] = "its own steps, by its tolerance (an adaptive pair; " + lanes[i].step_text + " s its first trial)";
  return how;
}

}  // namespace clothsim::clip
