// The work-precision study on the damped oscillator of spring.yaml (m = 1 kg, k = 100 N/m,
// d = 2 N s/m, 0.1 m initial stretch, one end pinned): convergence orders from the slopes,
// the reference against the closed form, and a reference that is not converged caught.
#include "study/work_precision.h"

#include <gtest/gtest.h>

#include <cmath>
#include <ctime>
#include <filesystem>

#include "test_support.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

using testing::scene_path;

Model spring_model(const std::vector<std::string>& sets = {}) {
  return build_model(load_scene(scene_path("spring.yaml"), sets));
}

WorkPrecisionSpec spring_spec(std::vector<IntegratorKind> kinds) {
  WorkPrecisionSpec spec;
  spec.integrators = std::move(kinds);
  spec.dts = {0.01, 0.005, 0.0025, 0.00125};  // w h = 0.1 .. 0.0125: the asymptotic range
  spec.duration = 1.0;
  spec.jobs = 2;
  return spec;
}

TEST(WorkPrecision, AReferenceComputedOnceIsReusedToTheBitAndAnotherSceneOrADamagedEntryMisses) {
  const std::string dir = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/wp_reference_cache";
  std::filesystem::remove_all(dir);
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4, IntegratorKind::Midpoint});
  spec.duration = 0.5;
  spec.reference_cache = {dir, 1ull << 30};
  const Model model = spring_model();
  const WorkPrecisionResult first = work_precision(model, spec);
  ASSERT_EQ(first.reference.cache, "stored");
  ASSERT_TRUE(std::filesystem::exists(first.reference.cache_file)) << first.reference.cache_file;
  const auto same = [&](const WorkPrecisionResult& r) {
    EXPECT_EQ(r.reference.change_rms, first.reference.change_rms);
    EXPECT_EQ(r.reference.steps, first.reference.steps) << "the totals of the runs that computed it";
    EXPECT_TRUE(r.reference_x == first.reference_x);
    ASSERT_EQ(r.points.size(), first.points.size());
    for (std::size_t k = 0; k < r.points.size(); ++k) {
      EXPECT_EQ(r.points[k].rms_error, first.points[k].rms_error) << k;
      EXPECT_EQ(r.points[k].max_error, first.points[k].max_error) << k;
      EXPECT_EQ(r.points[k].rms_error_at_end, first.points[k].rms_error_at_end) << k;
    }
  };
  const WorkPrecisionResult second = work_precision(model, spec);
  EXPECT_EQ(second.reference.cache, "reused");
  same(second);
  // Another scene (undamped) is another key; a truncated entry is recomputed, never served.
  EXPECT_EQ(work_precision(spring_model({"cloth.springs.structural.damping=0"}), spec).reference.cache, "stored");
  std::filesystem::resize_file(first.reference.cache_file, std::filesystem::file_size(first.reference.cache_file) / 2);
  const WorkPrecisionResult third = work_precision(model, spec);
  EXPECT_EQ(third.reference.cache, "stored");
  same(third);
  // Whether the cloth touches a collider at T is kept with it (the saved state is the cloth's
  // alone: it was read from past the positions' end).
  const Model touching = spring_model({"ground.height=-0.015", "collision.model=projection"});
  EXPECT_TRUE(work_precision(touching, spec).reference.contact_at_end);
  const WorkPrecisionResult again = work_precision(touching, spec);
  EXPECT_EQ(again.reference.cache, "reused");
  EXPECT_TRUE(again.reference.contact_at_end);
  spec.reference_cache = {};
  EXPECT_EQ(work_precision(model, spec).reference.cache, "off");
}

TEST(WorkPrecision, SlopesOnTheSpringGiveEachMethodsConvergenceOrder) {
  const Model model = spring_model();
  const WorkPrecisionResult r = work_precision(
      model, spring_spec({IntegratorKind::ExplicitEuler, IntegratorKind::SymplecticEuler, IntegratorKind::Midpoint,
                          IntegratorKind::Rk4, IntegratorKind::ImplicitEuler}));
  ASSERT_TRUE(r.reference.converged) << r.reference.failure;
  ASSERT_EQ(r.points.size(), 20u);
  EXPECT_NEAR(convergence_order(r.points, IntegratorKind::ExplicitEuler), 1.0, 0.2);
  EXPECT_NEAR(convergence_order(r.points, IntegratorKind::SymplecticEuler), 1.0, 0.2);
  EXPECT_NEAR(convergence_order(r.points, IntegratorKind::Midpoint), 2.0, 0.2);
  EXPECT_NEAR(convergence_order(r.points, IntegratorKind::Rk4), 4.0, 0.2);
  EXPECT_NEAR(convergence_order(r.points, IntegratorKind::ImplicitEuler), 1.0, 0.2);
  for (const WorkPrecisionPoint& p : r.points) {
    EXPECT_TRUE(p.finished);
    EXPECT_EQ(p.steps, std::llround(1.0 / p.dt));  // every run ends exactly at T
    EXPECT_LE(p.rms_error, p.max_error * (1 + 1e-12));
  }
}

TEST(WorkPrecision, TheOrderIsFittedOverTheCommonStepsOnly) {
  // Errors 1e-4 and 1e-3 at 1e-3 and 1e-2 s: first order. A frame-rate step of 1/30 s whose
  // error has saturated (w h >> 1) would pull the slope down; it is left out.
  std::vector<WorkPrecisionPoint> points(3);
  const double dts[] = {1e-3, 1e-2, 1.0 / 30.0}, errors[] = {1e-4, 1e-3, 2e-3};
  for (int i = 0; i < 3; ++i) {
    points[i].integrator = IntegratorKind::ImplicitEuler;
    points[i].dt = dts[i];
    points[i].rms_error = errors[i];
    points[i].finished = true;
  }
  points[2].frame_step = true;
  EXPECT_NEAR(convergence_order(points, IntegratorKind::ImplicitEuler), 1.0, 1e-12);
  points[2].frame_step = false;
  EXPECT_LT(convergence_order(points, IntegratorKind::ImplicitEuler), 0.9) << "what it would read with it";
}

TEST(WorkPrecision, FixedStepReferenceMatchesTheClosedFormOfTheDampedOscillator) {
  const Model model = spring_model();
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4});
  spec.adaptive_reference = false;  // the reference of a scene with projected contacts
  const WorkPrecisionResult r = work_precision(model, spec);
  ASSERT_EQ(r.reference_x.cols(), 2);
  // u'' + 2 u' + 100 u = 0, u(0) = 0.1, u'(0) = 0: zeta w0 = 1, wd = sqrt(99).
  const double wd = std::sqrt(99.0), t = 1.0;
  const double u = 0.1 * std::exp(-t) * (std::cos(wd * t) + std::sin(wd * t) / wd);
  const double length = (r.reference_x.col(1) - r.reference_x.col(0)).norm();
  EXPECT_NEAR(length - 1.0, u, 1e-10);
  EXPECT_LT(r.reference.change_rms, 1e-12);
  EXPECT_DOUBLE_EQ(r.reference.dt, 0.00125 / 16);
  EXPECT_FALSE(r.reference.adaptive);
}

TEST(WorkPrecision, ASmoothScenesReferenceIsAdaptiveAndMeetsTheClosedFormToItsEstimate) {
  const Model model = spring_model();
  const WorkPrecisionResult r = work_precision(model, spring_spec({IntegratorKind::Rk4}));
  ASSERT_TRUE(r.reference.adaptive);
  ASSERT_TRUE(r.reference.converged) << r.reference.failure;
  const double wd = std::sqrt(99.0), t = 1.0;
  const double u = 0.1 * std::exp(-t) * (std::cos(wd * t) + std::sin(wd * t) / wd);
  const double length = (r.reference_x.col(1) - r.reference_x.col(0)).norm();
  EXPECT_NEAR(length - 1.0, u, r.reference.change_max) << "within its own estimated error";
  EXPECT_LT(r.reference.change_rms, r.reference.round_off);
  EXPECT_EQ(r.reference.dt, 0.0);
}

TEST(WorkPrecision, ErrorsUnderTenTimesTheReferencesAreUnresolvedAndLeftOutOfTheOrder) {
  std::vector<WorkPrecisionPoint> points(3);
  const double dts[] = {1e-3, 2e-3, 4e-3}, errors[] = {1e-9, 1e-6, 8e-6};
  for (int i = 0; i < 3; ++i) {
    points[i].integrator = IntegratorKind::Midpoint;
    points[i].dt = dts[i];
    points[i].rms_error = errors[i];
    points[i].finished = true;
  }
  EXPECT_EQ(mark_unresolved(points, 1e-9, 0.1), 1);
  EXPECT_TRUE(points[0].unresolved);
  EXPECT_FALSE(points[1].unresolved);
  EXPECT_NEAR(convergence_order(points, IntegratorKind::Midpoint), 3.0, 1e-9) << "from the two resolved points";
}

TEST(WorkPrecision, AnErrorAtRoundOffIsNotAFailedReference) {
  // RK4 at w h = 1e-3 on the spring reaches round-off; so does a fixed-step RK4 reference 16x
  // finer: the points it cannot resolve are unresolved, and the reference is still converged.
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4});
  spec.dts = {1e-4, 2e-4};
  spec.duration = 0.2;
  spec.adaptive_reference = false;
  const WorkPrecisionResult r = work_precision(spring_model(), spec);
  EXPECT_LE(r.reference.change_rms, r.reference.round_off);
  EXPECT_GT(r.reference.unresolved, 0);
  EXPECT_TRUE(r.reference.converged) << r.reference.failure;
}

TEST(WorkPrecision, TheRoundOffFloorIsRelativeToTheStatesScale) {
  // The spring, centred on the origin, spans x in [-0.5, 0.6] m (its 0.1 m stretch): its floor
  // is 1e-11 x 0.6 m. The same spring a hundred metres away holds its coordinates to
  // eps x 100 m, so its floor is about 170x higher.
  const Model near = spring_model();
  EXPECT_NEAR(state_scale(near), 0.6, 1e-12);
  EXPECT_NEAR(round_off_floor(near), kRoundOffRelative * 0.6, 1e-24);
  Model far = near;
  far.initial_x.array() += 100.0;
  EXPECT_NEAR(round_off_floor(far), kRoundOffRelative * 100.6, 1e-22);
  EXPECT_GT(round_off_floor(far), 50 * round_off_floor(near));
}

TEST(WorkPrecision, ReferenceCheckFailsWhenTheReferenceIsNotConverged) {
  // A first-order reference only twice finer than the RK4 runs it judges: halving it moves
  // the answer by ~1e-4 m, so every "error" it reports is its own (RK4's are ~1e-8 m).
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4});
  spec.dts = {0.01, 0.005};
  spec.reference_integrator = IntegratorKind::SymplecticEuler;
  spec.reference_refinement = 2;
  spec.adaptive_reference = false;
  const WorkPrecisionResult r = work_precision(spring_model(), spec);
  EXPECT_TRUE(r.reference.finished);
  EXPECT_FALSE(r.reference.converged);
  EXPECT_EQ(r.reference.unresolved, 2) << "both RK4 runs: their errors are the reference's";
  EXPECT_GT(r.reference.change_rms, 1e-5);
  EXPECT_NE(r.reference.failure.find("not converged"), std::string::npos) << r.reference.failure;
}

TEST(WorkPrecision, DivergedRunIsKeptWithoutAnError) {
  // Undamped, explicit Euler at w h = 2.5 grows by |1 + 2.5 i| = 2.7 per step.
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::ExplicitEuler});
  spec.dts = {0.25, 0.125};
  spec.duration = 50.0;
  const WorkPrecisionResult r = work_precision(spring_model({"cloth.springs.structural.damping=0"}), spec);
  ASSERT_EQ(r.points.size(), 2u);
  const WorkPrecisionPoint& big = r.points[1];
  EXPECT_DOUBLE_EQ(big.dt, 0.25);
  EXPECT_TRUE(big.diverged);
  EXPECT_FALSE(big.finished);
  EXPECT_LT(big.diverged_at, 50.0);
  EXPECT_LT(big.steps, 200);  // stopped early, not run to T
  EXPECT_TRUE(std::isnan(big.rms_error));
  EXPECT_FALSE(big.reason.empty());
}

TEST(WorkPrecision, FrameRateStepsAreRunByImplicitEulerOnlyAndUnconvergedStepsAreCounted) {
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4, IntegratorKind::ImplicitEuler});
  spec.dts = {0.01, 0.005};
  spec.frame_dts = {0.02, 0.01, 0.04};  // 0.01 is also a common step: run once
  // Swinging under gravity the spring rotates, so one linearised step cannot meet 1e-10.
  const Model model = spring_model({"gravity=[0, -9.8, 0]", "implicit.newton_max_iterations=1",
                                    "implicit.newton_tolerance=1e-10"});
  const WorkPrecisionResult r = work_precision(model, spec);
  std::vector<double> rk4, implicit;
  for (const WorkPrecisionPoint& p : r.points) {
    (p.integrator == IntegratorKind::Rk4 ? rk4 : implicit).push_back(p.dt);
    if (p.integrator == IntegratorKind::Rk4) EXPECT_EQ(p.unconverged_steps, 0);
    else EXPECT_GT(p.unconverged_steps, p.steps / 2) << "one iteration at 1e-10 misses most steps";
  }
  EXPECT_EQ(rk4, (std::vector<double>{0.005, 0.01}));
  EXPECT_EQ(implicit, (std::vector<double>{0.005, 0.01, 0.02, 0.04}));
}

TEST(WorkPrecision, RejectsStepListsItCannotRun) {
  const Model model = spring_model();
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4});
  spec.dts = {};
  EXPECT_THROW(work_precision(model, spec), StudyError);
  spec.dts = {0.01, -0.005};
  EXPECT_THROW(work_precision(model, spec), StudyError);
  spec.dts = {0.003};
  try {
    checked(spec);
    FAIL() << "0.003 s does not divide 1 s";
  } catch (const StudyError& e) {
    EXPECT_NE(std::string(e.what()).find("0.003 does not divide the duration 1 s"), std::string::npos) << e.what();
  }
  spec.dts = {0.01, 0.01};
  EXPECT_THROW(checked(spec), StudyError);
  spec.dts = {0.02, 0.01};
  EXPECT_EQ(checked(spec).dts, (std::vector<double>{0.01, 0.02}));  // sorted
}

// An adaptive lane runs once per tolerance beside the fixed-step lanes' steps (DiffEqDevTools'
// work-precision set), and its error follows the tolerance: within 100x of it at every
// tolerance, falling with it at a slope near 1 (tolerance proportionality), each run landing
// on T.
TEST(WorkPrecision, AnAdaptiveLaneRunsOncePerToleranceAndItsErrorFollowsIt) {
  const Model model = spring_model();
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4, IntegratorKind::Dopri5, IntegratorKind::Rkf78});
  spec.tolerances = {1e-8, 1e-4, 1e-6};  // sorted loosest first
  spec.reference_tolerance = 1e-12;
  const WorkPrecisionResult r = work_precision(model, spec);
  ASSERT_TRUE(r.reference.finished);
  ASSERT_EQ(r.points.size(), 4u + 3u + 3u);
  for (std::size_t lane : {1u, 2u}) {
    std::vector<const WorkPrecisionPoint*> runs;
    for (const WorkPrecisionPoint& p : r.points)
      if (p.lane == lane) runs.push_back(&p);
    ASSERT_EQ(runs.size(), 3u);
    EXPECT_EQ(runs[0]->tolerance, 1e-4);
    EXPECT_EQ(runs[2]->tolerance, 1e-8);
    for (const WorkPrecisionPoint* p : runs) {
      ASSERT_TRUE(p->finished) << p->reason;
      EXPECT_FALSE(p->unresolved) << p->tolerance;
      EXPECT_LT(p->rms_error, 100.0 * p->tolerance) << p->tolerance;
      EXPECT_EQ(p->dt, 0.00125);  // the first trial: the smallest step
    }
    EXPECT_GT(runs[0]->rms_error, runs[2]->rms_error);
    EXPECT_GT(runs[0]->steps, 0);
    EXPECT_LT(runs[0]->steps, runs[2]->steps);  // a tighter tolerance takes more steps
    const double slope = lane_convergence_order(r.points, lane);
    EXPECT_GT(slope, 0.5) << "lane " << lane;
    EXPECT_LT(slope, 1.5) << "lane " << lane;
  }
  EXPECT_NEAR(lane_convergence_order(r.points, 0), 4.0, 0.2);  // rk4's is still its order
  EXPECT_TRUE(order_shortfall(r, IntegratorKind::Dopri5).empty());  // a slope against tol is no order
}

TEST(WorkPrecision, RefusesAnAdaptiveLaneWithoutTolerancesAndToleranceListsItCannotRun) {
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Dopri5});
  EXPECT_THROW(checked(spec), StudyError);
  spec.tolerances = {1e-6, 1e-6};
  EXPECT_THROW(checked(spec), StudyError);
  spec.tolerances = {0.0};
  EXPECT_THROW(checked(spec), StudyError);
  spec.tolerances = {1e-6, 1e-4};
  EXPECT_EQ(checked(spec).tolerances, (std::vector<double>{1e-4, 1e-6}));
}

TEST(WorkPrecision, StoppedStudyLeavesOutTheRunsNotMade) {
  StudyHooks hooks;
  hooks.stop = [] { return true; };
  const WorkPrecisionResult r = work_precision(spring_model(), spring_spec({IntegratorKind::Rk4}), hooks);
  EXPECT_FALSE(r.complete);
  EXPECT_TRUE(r.points.empty());
  EXPECT_FALSE(r.reference.converged);
}

TEST(PositionError, IsTheRmsAndMaxOverParticlesFreeInTheReference) {
  const Model model = spring_model();  // particle 0 pinned, 1 free
  Eigen::Matrix3Xd a = Eigen::Matrix3Xd::Zero(3, 2), b = Eigen::Matrix3Xd::Zero(3, 2);
  a.col(0) << 5, 0, 0;  // pinned: ignored
  a.col(1) << 3, 4, 0;
  Eigen::VectorXd inv_mass(2);
  inv_mass << 0.0, 1.0;
  const PositionError e = position_error(model, a, b, inv_mass);
  EXPECT_DOUBLE_EQ(e.rms, 5.0);
  EXPECT_DOUBLE_EQ(e.max, 5.0);
}

TEST(ConvergenceOrder, IsTheLeastSquaresSlopeOfLogErrorAgainstLogStep) {
  std::vector<WorkPrecisionPoint> points;
  for (double dt : {0.1, 0.05, 0.025}) {
    WorkPrecisionPoint p;
    p.integrator = IntegratorKind::Midpoint;
    p.dt = dt;
    p.finished = true;
    p.rms_error = 3.0 * dt * dt;
    points.push_back(p);
  }
  EXPECT_NEAR(convergence_order(points, IntegratorKind::Midpoint), 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(convergence_order(points, IntegratorKind::Rk4)));
}

// A study whose `kind` runs at `dts` with errors `errors` against a converged reference.
WorkPrecisionResult synthetic_study(IntegratorKind kind, const std::vector<double>& dts,
                                    const std::vector<double>& errors, double duration) {
  WorkPrecisionResult r;
  r.duration = duration;
  r.reference.finished = r.reference.converged = true;
  r.reference.change_rms = 1e-12;
  for (std::size_t i = 0; i < dts.size(); ++i) {
    WorkPrecisionPoint p;
    p.integrator = kind;
    p.dt = dts[i];
    p.finished = true;
    p.rms_error = p.max_error = errors[i];
    r.points.push_back(p);
  }
  return r;
}

bool mentions(const std::vector<std::string>& lines, const std::string& what) {
  for (const std::string& line : lines)
    if (line.find(what) != std::string::npos) return true;
  return false;
}

TEST(OrderShortfall, IsSilentWhereTheOrderHolds) {
  const WorkPrecisionResult r = synthetic_study(IntegratorKind::Rk4, {1e-3, 2e-3, 4e-3}, {1e-8, 16e-8, 256e-8}, 1.0);
  EXPECT_TRUE(order_shortfall(r, IntegratorKind::Rk4).empty());
  EXPECT_TRUE(order_shortfall(r, IntegratorKind::Midpoint).empty()) << "no points: nothing to explain";
}

TEST(OrderShortfall, NamesContactWhenErrorsLevelOffWithTheClothOnASphere) {
  WorkPrecisionResult r = synthetic_study(IntegratorKind::Rk4, {1e-4, 2e-4, 4e-4}, {6e-3, 6.1e-3, 6.2e-3}, 1.6);
  std::vector<std::string> why = order_shortfall(r, IntegratorKind::Rk4);
  EXPECT_FALSE(mentions(why, "contact-limited"));
  ASSERT_EQ(why.size(), 1u) << "no cause found: the general advice";
  EXPECT_TRUE(mentions(why, "smaller --dts")) << why[0];
  r.reference.contact_at_end = true;
  why = order_shortfall(r, IntegratorKind::Rk4);
  ASSERT_EQ(why.size(), 1u);
  EXPECT_TRUE(mentions(why, "contact-limited")) << why[0];
  EXPECT_TRUE(mentions(why, "--duration")) << why[0];
}

TEST(OrderShortfall, NamesAnUnconvergedReferenceAndAShortT) {
  WorkPrecisionResult r = synthetic_study(IntegratorKind::Midpoint, {0.01, 0.02, 0.04}, {1e-6, 1.5e-6, 2e-6}, 0.4);
  r.reference.change_rms = 1e-7;  // within 30x of the smallest error
  const std::vector<std::string> why = order_shortfall(r, IntegratorKind::Midpoint);
  EXPECT_TRUE(mentions(why, "reference not converged"));
  EXPECT_TRUE(mentions(why, "--reference-refinement"));
  EXPECT_TRUE(mentions(why, "T too short")) << "0.4 s holds 10 steps of 0.04 s";
}

TEST(WorkPrecision, TheReferenceSaysWhetherTheClothTouchesTheGroundAtT) {
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::Rk4});
  spec.dts = {0.01};
  EXPECT_FALSE(work_precision(spring_model(), spec).reference.contact_at_end);
  // The free end stays at y = 0, 0.015 m above the ground: within two margins (0.02 m).
  EXPECT_TRUE(work_precision(spring_model({"ground.height=-0.015"}), spec).reference.contact_at_end);
  // Under the barrier the same touch is a smooth force: bench said "a contact is resolved once
  // per step" of the barrier drape's push.
  EXPECT_FALSE(work_precision(spring_model({"ground.height=-0.015", "collision.model=barrier"}), spec)
                   .reference.contact_at_end);
}

// Two lanes of one integrator, each with its own settings: the points carry their lane, each
// lane's order is fitted over its own points, and a lane runs its settings' solver.
TEST(WorkPrecision, LanesOfOneIntegratorRunWithTheirOwnSettings) {
  const Model model = spring_model();
  MethodSettings fixed_point = model.method_defaults();
  fixed_point.implicit.solver = ImplicitSolver::FixedPoint;
  fixed_point.implicit.fixed_point_iterations = 1;
  WorkPrecisionSpec spec = spring_spec({IntegratorKind::ImplicitEuler, IntegratorKind::ImplicitEuler});
  spec.dts = {0.01, 0.005};
  spec.lane_names = {"implicit_euler", "implicit_euler_fixed_point"};
  spec.lane_settings = {model.method_defaults(), fixed_point};
  const WorkPrecisionResult r = work_precision(model, spec);
  ASSERT_EQ(r.points.size(), 4u);
  EXPECT_EQ(r.points[0].lane, 0u);
  EXPECT_EQ(r.points[3].lane, 1u);
  EXPECT_EQ(r.points[2].newton_iterations, r.points[2].steps);  // the fixed point's one iteration a step
  EXPECT_NE(r.points[0].rms_error, r.points[2].rms_error);
  EXPECT_NEAR(lane_convergence_order(r.points, 0), 1.0, 0.2);
  EXPECT_NEAR(lane_convergence_order(r.points, 1), 1.0, 0.3);
  spec.lane_names = {"implicit_euler", "implicit_euler"};
  EXPECT_THROW(checked(spec), StudyError);
}

// A 16 x 16 sheet pinned at its corners, lightly damped (w_max ~ 63 rad/s): every step below
// 1 ms runs to the end for the explicit family, so each run costs what its plan says.
const char* kProgressSheet = R"(
name: sheet
dt: 1.0e-4
cloth: {particles: [16, 16], size: [1, 1], pinned: corners,
        springs: {structural: {stiffness: 500, damping: 0.5}}}
)";

TEST(WorkPrecision, ProgressWeighsEachRunByItsCostSoTheFirstEstimateOfTimeLeftHolds) {
  // The reference's two runs go first (the points are measured against them as they run), then
  // the points dearest first: by count the first report (the reference, half the work) says 9
  // runs' worth is left; by its share of the cost estimates the time left is within 2x.
  // Process CPU time on one thread stands for the time, so a busy machine does not move it.
  const Model model = clothsim::testing::model_from_yaml(kProgressSheet);
  WorkPrecisionSpec spec;
  spec.integrators = {IntegratorKind::SymplecticEuler, IntegratorKind::Midpoint, IntegratorKind::Rk4};
  spec.dts = {2.5e-4, 5e-4, 1e-3};
  spec.duration = 1.0;
  spec.adaptive_reference = false;
  spec.jobs = 1;
  std::vector<std::pair<double, StudyProgress>> seen;  // (CPU s, progress) at each run's end
  StudyHooks hooks;
  hooks.progress = [&](const StudyProgress& p) { seen.emplace_back(std::clock() / double(CLOCKS_PER_SEC), p); };
  const double start = std::clock() / double(CLOCKS_PER_SEC);
  const WorkPrecisionResult r = work_precision(model, spec, hooks);
  ASSERT_TRUE(r.complete);
  ASSERT_EQ(seen.size(), 10u) << "the reference's two runs, then 9 points";
  const auto& [at, first] = seen.front();
  const double elapsed = at - start, left = seen.back().first - at;
  ASSERT_GT(left, 0.0);
  EXPECT_EQ(first.done, 2);
  EXPECT_GT(first.share(), 0.3) << "the dearest run is a large share";
  EXPECT_LT(first.share(), 1.0);
  const double by_share = elapsed * (1.0 - first.share()) / first.share();
  const double by_count = elapsed * static_cast<double>(first.total - first.done) / static_cast<double>(first.done);
  EXPECT_GT(by_share, left / 2.0) << "elapsed " << elapsed << " s, share " << first.share() << ", left " << left << " s";
  EXPECT_LT(by_share, left * 2.0) << "elapsed " << elapsed << " s, share " << first.share() << ", left " << left << " s";
  EXPECT_GT(by_count, left * 2.0) << "the count's estimate: what the share corrects";
  EXPECT_DOUBLE_EQ(seen.back().second.share(), 1.0);
}

}  // namespace
}  // namespace clothsim::analysis

TEST(ParetoFront, IsTheCheapestRunToEachErrorLevelAmongTheRunsThatCount) {
  using clothsim::analysis::WorkPrecisionPoint;
  const auto point = [](std::size_t lane, double err, double cpu) {
    WorkPrecisionPoint p;
    p.lane = lane;
    p.finished = true;
    p.rms_error = err;
    p.cpu_seconds = cpu;
    return p;
  };
  std::vector<WorkPrecisionPoint> points{point(0, 3e-2, 1.0), point(0, 3e-3, 4.0), point(1, 5e-3, 2.0),
                                         point(1, 2e-5, 3.0), point(2, 1e-6, 0.5)};
  points[4].wrong = true;  // cheapest and most accurate, but not this scene's physics: never chosen
  const auto front = clothsim::analysis::pareto_front(points);
  ASSERT_EQ(front.size(), 4u) << "1e-1 .. 1e-4: nothing that counts reaches 1e-5";
  EXPECT_EQ(front[0].point, 0u) << "1e-1: the cheapest run under it";
  EXPECT_EQ(front[1].point, 2u) << "1e-2: lane 1 at 2 s beats lane 0's 3e-2 (above) and 4 s";
  EXPECT_EQ(front[2].point, 3u) << "1e-3: only 3e-3 (lane 0, too large) and 2e-5 qualify";
  EXPECT_EQ(front[3].point, 3u);
  EXPECT_DOUBLE_EQ(front[3].level, 1e-4);
  points[3].unresolved = true;  // an error under the reference's own is no number to choose by
  EXPECT_EQ(clothsim::analysis::pareto_front(points).size(), 2u);
}
