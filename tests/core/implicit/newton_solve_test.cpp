// The Newton solve's records (newton_solve.h): the matrix-reuse phases and their transitions,
// and the trace, which goes only where the tool sends it and changes no number.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "test_support.h"
#include "core/implicit/newton_solve.h"
#include "core/simulation.h"
#include "scene/build_model.h"

namespace clothsim::testing {
namespace {

constexpr IntegratorKind kKind = IntegratorKind::ImplicitEuler;

TEST(MatrixReuse, ATrialThatServesKeepsReuseAllowedAndTrusted) {
  MatrixReuse reuse;
  reuse.phase = MatrixReuse::Phase::Allowed;
  reuse.trusted = false;
  reuse.start_trial(2.0);
  EXPECT_EQ(reuse.phase, MatrixReuse::Phase::OnTrial);
  EXPECT_EQ(reuse.trial_from, 2.0);
  reuse.judge(true);
  EXPECT_EQ(reuse.phase, MatrixReuse::Phase::Allowed);
  EXPECT_TRUE(reuse.trusted);
  EXPECT_EQ(reuse.unserved, 0);
}

TEST(MatrixReuse, ATrialThatFailsBarsReuseAndIsNotChargedToTheBudget) {
  for (const bool judged : {true, false}) {
    MatrixReuse reuse;
    reuse.phase = MatrixReuse::Phase::Allowed;
    reuse.start_trial(1.0);
    if (judged) reuse.judge(false);
    else reuse.fail();  // no descent or no step
    EXPECT_EQ(reuse.phase, MatrixReuse::Phase::Barred);
    EXPECT_FALSE(reuse.allowed());
    EXPECT_FALSE(reuse.trusted);
    EXPECT_EQ(reuse.unserved, 1);
  }
}

TEST(StallWatch, CallsAStallOnlyAfterAWindowWithNeitherTheResidualHalvingNorPhiFalling) {
  StallWatch watch;
  const PotentialValue flat{-10.0, 100.0};
  EXPECT_FALSE(watch.stalled(0, 1.0, flat, 5));  // the first iterate marks
  for (int k = 1; k < 5; ++k) EXPECT_FALSE(watch.stalled(k, 0.9, flat, 5)) << k;
  EXPECT_TRUE(watch.stalled(5, 0.9, flat, 5));
  // The residual halving from the mark's is progress...
  EXPECT_FALSE(watch.stalled(6, 0.5, flat, 5));
  EXPECT_EQ(watch.mark, 6);
  // ...and so is Phi falling by more than a millionth of its size, whatever the residual.
  EXPECT_FALSE(watch.stalled(11, 0.9, PotentialValue{-10.001, 100.0}, 5));
  EXPECT_EQ(watch.mark, 11);
  // A fall of Phi within rounding is not.
  for (int k = 12; k < 16; ++k) EXPECT_FALSE(watch.stalled(k, 0.9, PotentialValue{-10.001 - 1e-12 * k, 100.0}, 5));
  EXPECT_TRUE(watch.stalled(16, 0.9, PotentialValue{-10.001 - 1e-12 * 16, 100.0}, 5));
}

// Frame-rate steps 1/240 .. 1/30 s with default settings: every step converges.
std::int64_t unconverged_steps(const std::string& scene, double h, std::vector<std::string> sets) {
  sets.push_back("dt=" + std::to_string(h));
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/" + scene, sets));
  clothsim::Run run(model, kKind, h);
  EXPECT_TRUE(run.advance_to(model.duration)) << scene << " h " << h;
  return run.totals().unconverged_steps;
}
constexpr double kFrameSteps[] = {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30};

TEST(ImplicitEuler, ConvergesAtEveryFrameRateStepOfTheStiffSceneAndTheDrapeByDefault) {
  for (const double h : kFrameSteps) {
    EXPECT_EQ(unconverged_steps("stiff.yaml", h, {}), 0) << "h " << h;
    EXPECT_EQ(unconverged_steps("drape.yaml", h, {"duration=2.5"}), 0) << "h " << h;
  }
}

TEST(ImplicitEuler, ConvergesAtEveryFrameRateStepOfStifferAndHeavierSheetsByDefault) {
  // k up to 1e7 N/m and particles up to 5 kg, falling on the stiff scene's ball and on a
  // small one (0.3 m): the cases that left steps at the old cap of 20 iterations.
  const std::vector<std::string> stiffer{"cloth.springs.structural.stiffness=1e7",
                                         "cloth.springs.shear.stiffness=1e7",
                                         "cloth.springs.bend.stiffness=1e6", "cloth.particle_mass=5",
                                         "duration=1.5"};
  std::vector<std::string> small_ball = stiffer;
  small_ball.push_back("spheres.0.radius=0.3");
  for (const double h : {1.0 / 60, 1.0 / 30}) {
    EXPECT_EQ(unconverged_steps("stiff.yaml", h, stiffer), 0) << "h " << h;
    EXPECT_EQ(unconverged_steps("stiff.yaml", h, small_ball), 0) << "h " << h;
  }
}

TEST(ImplicitEuler, BaraffWitkinsStepStaysOneLinearisedSolve) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml",
                                             {"implicit.newton_max_iterations=1", "dt=0.03333333333333333"}));
  clothsim::Run run(model, kKind, model.dt);
  ASSERT_TRUE(run.advance_to(1.0));
  EXPECT_EQ(run.totals().newton_iterations, run.totals().steps);
}

TEST(NewtonTrace, GoesOnlyToTheSinkTheToolGivesAndChangesNoNumber) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml",
                                             {"dt=0.03333333333333333"}));
  State quiet = initial_state(model), traced = quiet;
  Workspace quiet_ws, traced_ws;
  std::vector<std::string> lines;
  traced_ws.newton_trace = [&lines](const char* line) { lines.emplace_back(line); };
  for (int n = 0; n < 10; ++n) {
    step(model, quiet, kKind, model.dt, quiet_ws);
    step(model, traced, kKind, model.dt, traced_ws);
  }
  EXPECT_EQ((quiet.x - traced.x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((quiet.v - traced.v).cwiseAbs().maxCoeff(), 0.0);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front().rfind("newton step 0 start:", 0), 0u) << lines.front();
  int starts = 0;
  for (const std::string& line : lines) starts += line.find(" start: held ") != std::string::npos;
  EXPECT_EQ(starts, 10);
}

}  // namespace
}  // namespace clothsim::testing
