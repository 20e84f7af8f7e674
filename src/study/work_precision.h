// Work precision: how much error each integrator buys for how much work.
//
// For every integrator and step dt, the scene is run to time T and its cloth positions
// compared with a reference solution at K sample times on the way (sample_times: up to
// kMaxSamples evenly spaced times every step lands on, T the last): RMS and largest
// particle-position difference over the particles free then, at each time. A run's error is
// the largest over the times (L-infinity in time, as DiffEqDevTools' default `:l∞` measures;
// spec.error_over_time), or the error at T alone; both are kept. The error at T alone can
// flatter a method whose error passes near zero at T: RK4 on the 13 x 13 barrier drape is 100x
// below its largest over the window at the end. Cost is recorded as wall time, CPU time of the
// run's thread and force evaluations (plus Newton and CG iterations for implicit Euler,
// whose force-evaluation count leaves out its linear solves). A run that diverges stops
// there and is kept as a marked point without an error.
//
// The reference. No closed form exists for a cloth, so the program computes one. On a smooth
// scene (reference.h, smooth_scene: no contact resolved by projection) it is an adaptive
// Dormand-Prince solve at a tolerance of reference_tolerance, and again at 100x tighter; the
// difference between those two is the reference's estimated error, and errors are measured
// against the tighter. On a scene with projected contacts it is RK4 (a
// fourth-order method, the most accurate of the five) at h = smallest dt / 8, and again at
// h / 2. The difference between those two is how far the reference itself may be from the
// truth (for a smooth problem it is ~15/16 of the coarser one's error; a collision makes
// convergence rougher, which this figure measures rather than assumes). The study is
// trustworthy only if that figure is much smaller than every error it reports: the check
// asks for at most a tenth of the smallest RMS error, and a result that fails it says so
// (the CLI then exits non-zero). Errors are measured against the finer run.
//
// A point whose RMS error is under 1 / reference_margin (10) times the reference's estimated
// error is unresolved: the reference cannot tell its error, so no number is given, and the
// order is fitted without it. Unresolved points fail the check only when the reference is
// above round-off (round_off_floor): an error at round-off (RK4 reaching 4e-14 m on a
// ball-less cloth) is not a reference that failed.
//
// Every dt must divide T (T / dt a whole number within 1e-9): then every run, the
// reference included, ends exactly at T, and no error is a comparison of two times.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "study.h"
#include "reference_cache.h"
#include "study_run.h"
#include "core/integrators/integrator_kind.h"
#include "core/model/model.h"

namespace clothsim::analysis {

struct WorkPrecisionSpec {
  std::vector<IntegratorKind> integrators;  // the study's lanes, in order
  // Per lane (each empty, or one per integrators entry): its name, unique, as rows and plots
  // label it (empty: the integrator's), and the method settings it runs with on the study's
  // model (empty: the model's own), so one integrator may run as several lanes (implicit_euler
  // and its fixed point, xpbd:10) without a copy of the model.
  std::vector<std::string> lane_names;
  std::vector<MethodSettings> lane_settings;
  std::vector<double> dts;     // s, each > 0 and dividing duration
  // The adaptive lanes' tolerances (rtol = atol, adaptive.h), each in (0, 1): an adaptive lane
  // (bs3, dopri5, rkf78) runs once per tolerance where a fixed-step lane runs once per step,
  // its first trial step `first_step` (0: the smallest of dts), landing on T.
  std::vector<double> tolerances;
  double first_step = 0.0;
  // The error a point is judged by (rms_error, max_error: its order, the Pareto front, the
  // unresolved rule, the plot): the largest over the sample times (true), or at T (false).
  bool error_over_time = true;
  std::vector<double> frame_dts;  // s, steps implicit_euler also runs (one step per video
                                  // frame: 1/240 .. 1/30 s), each > 0 and dividing duration
  double duration = 0.0;       // T, s
  IntegratorKind reference_integrator = kReferenceIntegrator;
  bool adaptive_reference = true;  // on a smooth scene, the adaptive reference (reference.h)
  double reference_tolerance = 1e-11;  // its tolerance (the second solve's is 100x tighter)
  int reference_refinement = 8;    // reference step = smallest dt / this (then halved once more)
  double reference_margin = 0.1;   // converged: halving's change <= margin x smallest error
  // Where the reference is kept between runs (reference_cache.h): dir "" (the default here)
  // computes it every time; bench sets it from the environment.
  ReferenceCacheSettings reference_cache;
  int jobs = 0;                    // threads; <= 0: hardware_concurrency
};

struct WorkPrecisionPoint {
  IntegratorKind integrator{};
  std::size_t lane = 0;            // index into spec.integrators
  double dt = 0.0;                 // s; an adaptive point's first trial step
  double tolerance = 0.0;          // an adaptive point's rtol = atol (spec.tolerances); 0: a fixed step
  bool frame_step = false;         // one of implicit Euler's frame-rate steps, outside the
                                   // common list (spec.frame_dts)
  bool finished = false;           // reached T (false: diverged, or stopped by the caller)
  bool diverged = false;
  double diverged_at = 0.0;        // s, when diverged
  std::string reason;              // why it diverged
  std::int64_t steps = 0, force_evals = 0, newton_iterations = 0, cg_iterations = 0;
  std::int64_t unconverged_steps = 0;  // implicit steps that ended above their tolerance
  std::int64_t rejected_steps = 0;     // an adaptive point's refused trials
  bool wrong = false;              // finite but WRONG (core/diagnostics.h): energy made, over-stretched
  double wrong_at = 0.0;           // s, when first
  std::string wrong_reason;
  double wall_seconds = 0.0, cpu_seconds = 0.0;
  bool unresolved = false;         // finished, but its error under 1 / margin x the reference's
  // m, the error the study judges by (spec.error_over_time: the two below or the two at T);
  // NaN unless finished.
  double rms_error = 0.0;          // RMS over the free particles
  double max_error = 0.0;          // largest particle distance
  double rms_error_at_end = 0.0, max_error_at_end = 0.0;      // at T
  double rms_error_over_time = 0.0, max_error_over_time = 0.0;  // the largest over the samples
  int samples = 0;                 // sample times the run landed on and was measured at
};

// At most this many sample times: enough to find a run's worst moment on the scenes' motions
// (a fall, a contact, a push: each tenths of a second at the default T of 0.5 s), few enough
// that the reference's kept positions stay small beside a run's (K x 3P doubles).
inline constexpr int kMaxSamples = 40;
// The study's sample times: T k / K for k = 1..K, K the largest up to kMaxSamples for which
// every one of spec.dts lands on T / K (an implicit frame step, spec.frame_dts, is measured at
// the times it lands on, T among them); T alone when no such K above 1 exists.
std::vector<double> sample_times(const WorkPrecisionSpec& spec);
// Sets p.rms_error and p.max_error to the error the study judges by.
void judge_error(WorkPrecisionPoint& p, bool over_time);

// Round-off is relative: a double holds a coordinate of size L to eps L (2.2e-16 L), and a
// run of 1e5..1e6 steps adds that up to about 1e-13 L (measured: RK4's two reference runs on
// the ball-less 25 x 25 drape differ by 1.9e-14 m RMS with L = 1 m). An error under
// kRoundOffRelative x L, 100x above that, is round-off: no double-precision reference could
// resolve it, so it fails no reference check.
inline constexpr double kRoundOffRelative = 1e-11;
// L (m): the largest |coordinate| of the scene's bodies at t = 0, sphere radii added, at least
// the cloth's own extent (a scene far from the origin holds its coordinates to eps L too).
double state_scale(const Model& model);
// kRoundOffRelative x state_scale(model), m: the error floor of that scene's references.
double round_off_floor(const Model& model);

struct ReferenceCheck {
  IntegratorKind integrator = kReferenceIntegrator;
  bool adaptive = false;           // the adaptive Dormand-Prince pair (then integrator and dt
  double tolerance = 0.0;          // do not apply): at tolerance and tolerance / 100
  double dt = 0.0;                 // s, the finer reference step (errors are measured against it)
  double change_rms = 0.0;         // m, RMS difference between the runs at 2 dt and dt (or the
                                   // two tolerances): the reference's estimated error, over
                                   // time or at T as the points' errors are (error_over_time)
  double change_max = 0.0;         // m, largest particle difference between them
  bool over_time = true;           // the errors are the largest over the sample times
  int samples = 0;                 // how many (1: T alone)
  std::int64_t steps = 0, force_evals = 0;  // both reference runs': what the reference cost
  double cpu_seconds = 0.0;
  double smallest_error = 0.0;     // m, smallest RMS error resolved (NaN when none)
  int unresolved = 0;              // finished points under 1 / margin x change_rms
  double margin = 0.1;
  double round_off = 0.0;          // m, round_off_floor(model): a change under it is round-off
  bool finished = false;           // both reference runs reached T
  bool converged = false;          // finished, and change_rms <= margin x smallest_error
  bool contact_at_end = false;     // contacts are projected, and a free particle of the finer
                                   // reference lies within two margins of a sphere or the ground at T
  bool velocity_forces = false;    // the model's forces depend on velocity (dampers, drag)
  std::string failure;             // why not converged, one sentence (empty when converged)
  // The cache (spec.reference_cache): "off", "reused" (steps, force_evals and cpu_seconds are
  // then the run that computed it), "stored" or "not stored: WHY"; cache_file its entry.
  std::string cache = "off";
  std::string cache_file;
};

struct WorkPrecisionResult {
  double duration = 0.0;           // T, s
  ReferenceCheck reference;
  Eigen::Matrix3Xd reference_x;    // (3 x P) cloth particle positions of the finer reference at T
  std::vector<WorkPrecisionPoint> points;  // integrator by integrator (spec order), dt ascending
                                           // (implicit_euler's include the frame_dts)
  bool complete = true;            // false when stopped early (points not run are left out)
};

// The steps `kind` runs: spec.dts, and for implicit_euler the frame_dts too, ascending.
std::vector<double> steps_of(const WorkPrecisionSpec& spec, IntegratorKind kind);

// The study's points in the order it reports them (integrator by integrator, dt ascending),
// not yet run: a point's index is its item number in a sharded bench (shard.h).
std::vector<WorkPrecisionPoint> planned_points(const WorkPrecisionSpec& spec);
// Lane `i`'s name (spec.lane_names, else the integrator's) and settings (spec.lane_settings,
// else `model`'s own).
std::string lane_name(const WorkPrecisionSpec& spec, std::size_t i);
MethodSettings lane_settings(const WorkPrecisionSpec& spec, std::size_t i, const Model& model);
// Rough cost of a run in force-evaluation equivalents, for scheduling and sharding only.
double cost_estimate(IntegratorKind kind, double T, double dt);
double point_cost(const WorkPrecisionPoint& p, double T);
// Runs point `p` of the study on `model` under its lane's settings (lane_settings): a fixed
// step, or an adaptive pair at the point's tolerance, to T, measured on the way by `sampling`.
StudyRun run_point(const Model& model, const WorkPrecisionSpec& spec, const WorkPrecisionPoint& p,
                   const std::function<bool()>& stop = {}, const Sampling& sampling = {});
// `p` with the run's outcome and cost, and its error at T against `reference` (nullptr: none);
// the error over time is the caller's (run_points measures it as the run goes).
WorkPrecisionPoint measured_point(WorkPrecisionPoint p, const StudyRun& run, const Model& model,
                                  const State* reference);

// Checks the spec (throws StudyError naming the problem) and returns it with dts sorted.
WorkPrecisionSpec checked(WorkPrecisionSpec spec);

// Whether the study's reference is the adaptive one on `model` (spec.adaptive_reference and a
// smooth scene), and its run: `finer` the tighter (or the finer step's) of the two.
bool uses_adaptive_reference(const Model& model, const WorkPrecisionSpec& spec);
StudyRun reference_run(const Model& model, const WorkPrecisionSpec& spec, bool finer,
                       const std::function<bool()>& stop = {}, const Sampling& sampling = {});
// Marks the finished points whose error the reference cannot resolve (WorkPrecisionPoint::
// unresolved) and returns how many.
int mark_unresolved(std::vector<WorkPrecisionPoint>& points, double reference_error, double margin);

// Runs the study: the two reference runs and every (integrator, dt), spread over the cores.
WorkPrecisionResult work_precision(const Model& model, const WorkPrecisionSpec& spec,
                                   const StudyHooks& hooks = {});

// Cloth-position differences over the particles free in `b` (inv_mass > 0): RMS and max, m.
struct PositionError {
  double rms = 0.0, max = 0.0;
};
PositionError position_error(const Model& model, const Eigen::Matrix3Xd& a,
                             const Eigen::Matrix3Xd& b, const Eigen::VectorXd& free_in_b);

// Observed order of convergence: least-squares slope of log(RMS error) against log(dt) over
// the finished points of `kind` at the common steps (NaN with fewer than two). The frame-rate
// steps are left out: there w h >> 1, far from the asymptotic regime an order describes.
// An adaptive lane's points fit log(RMS error) against log(tolerance) instead: the slope is its
// tolerance proportionality (1: the error follows the tolerance), not an order.
double convergence_order(const std::vector<WorkPrecisionPoint>& points, IntegratorKind kind);
double lane_convergence_order(const std::vector<WorkPrecisionPoint>& points, std::size_t lane);

// The decision a user is making: for each error level (a decade, 1e-1 m down to the smallest
// error measured), the run of least CPU whose RMS error at T is at or below it, among the runs
// that finished, converged, were not WRONG and were resolved (an error under the reference's
// own is no number to choose by). Levels no run reaches are left out.
struct ParetoLevel {
  double level = 0.0;  // m
  std::size_t point = 0;  // index into the points
};
std::vector<ParetoLevel> pareto_front(const std::vector<WorkPrecisionPoint>& points);

// The order each method has on a smooth problem (docs/cli.md, "The integrators"): 1, 1, 2, 4, 1.
int nominal_order(IntegratorKind kind);

// Why `kind`'s observed order is under half its nominal order, and what to try, one sentence
// per cause found: the reference not converged, or within 30x of the errors it judges; the
// cloth touching a sphere or the ground at T (contact-limited: a contact is resolved once per
// step, a non-smooth correction no method's order survives); errors at round-off; T holding
// fewer than 20 of the largest steps (T too short); else the steps outside the asymptotic
// range. Empty when the order is not that low or cannot be measured.
std::vector<std::string> order_shortfall(const WorkPrecisionResult& r, IntegratorKind kind);
// The same for one lane of `kind` (its points only).
std::vector<std::string> lane_order_shortfall(const WorkPrecisionResult& r, std::size_t lane, IntegratorKind kind);

}  // namespace clothsim::analysis
