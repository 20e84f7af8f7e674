// The words on a lane's picture (src/clip/frames/overlay_text.h): the overlay lines, and the banners
// a frame carries for a run's results: DIVERGED with the time and step as `run` prints them,
// and NOT CONVERGED with the count of missed implicit steps, in the singular for one.
#include "clip/frames/overlay_text.h"

#include <gtest/gtest.h>

#include "scene/lane.h"  // integrator_label

namespace clothsim::clip {
namespace {

TEST(OverlayText, MarksADivergedFrameWithItsTimeStepAndReason) {
  RenderFrame frame;
  frame.overlay_lines = {"t = 0.024 s"};
  mark_diverged(frame, Divergence{241, 0.0241, "strain 12.3 > 10"});
  EXPECT_EQ(frame.banner, (std::vector<std::string>{"DIVERGED", "at t = 0.0241 s", "(step 241)"}))
      << "phrases a narrow tile may put on two lines";
  ASSERT_EQ(frame.overlay_lines.size(), 2u);
  EXPECT_EQ(frame.overlay_lines.back(), "diverged: strain 12.3 > 10");
}

TEST(OverlayText, ADivergedCaptionHoldsTheTimeAndTheStepPredictedStable) {
  RenderFrame frame;
  mark_diverged(frame, Divergence{53, 0.0212, "kinetic energy 2.45e+09 J exceeds the bound 4.08e+08 J"}, 1.55e-4);
  EXPECT_EQ(frame.banner, (std::vector<std::string>{"DIVERGED", "at t = 0.0212 s", "(step 53)"}));
  EXPECT_EQ(frame.overlay_lines,
            (std::vector<std::string>{"diverged: kinetic energy 2.45e+09 J exceeds the bound 4.08e+08 J",
                                      "stable below ~0.00015 s (estimate)"}));
  // Where a sheet does not repeat the picture, the same in one block.
  EXPECT_EQ(diverged_caption(Divergence{53, 0.0212, "strain 12.3 > 10"}, 1.55e-4),
            (std::vector<std::string>{"DIVERGED at t = 0.0212 s (step 53)", "strain 12.3 > 10",
                                      "stable below ~0.00015 s (estimate)"}));
}

TEST(OverlayText, TheStableStepLineSaysNoneWhereNoStepIsStableAndNothingWithoutALimit) {
  EXPECT_EQ(stable_step_line(0.0), "no stable step (estimate)");  // undamped explicit Euler
  EXPECT_EQ(stable_step_line(std::numeric_limits<double>::infinity()), "");  // backward Euler
  EXPECT_EQ(stable_step_line(std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_EQ(diverged_caption(Divergence{3, 0.5, "non-finite position"}, std::numeric_limits<double>::infinity()),
            (std::vector<std::string>{"DIVERGED at t = 0.5 s (step 3)", "non-finite position"}));
}

TEST(OverlayText, CountsMissedImplicitStepsInTheNotConvergedBanner) {
  RenderFrame frame;
  mark_not_converged(frame, 1);
  EXPECT_EQ(frame.banner, (std::vector<std::string>{"NOT CONVERGED", "(1 step)"}));
  mark_not_converged(frame, 2);
  EXPECT_EQ(frame.banner, (std::vector<std::string>{"NOT CONVERGED", "(2 steps)"}));
  EXPECT_TRUE(frame.overlay_lines.empty()) << "the banner alone: the lane goes on";
}

TEST(OverlayText, OverlayLinesAreTheSceneTheLaneAndTheTimeHoweverTheLaneIsGiven) {
  Model model;
  model.name = "drape";
  EXPECT_EQ(overlay_lines(model, integrator_label("implicit_euler", "1/60"), 1.5),
            (std::vector<std::string>{"drape", "implicit_euler  dt = 1/60 s", "t = 1.500 s"}));
  // From the integrator and its step: the same lines, the step written %.3g.
  EXPECT_EQ(overlay_lines(model, IntegratorKind::Rk4, 1e-4, 0.25),
            (std::vector<std::string>{"drape", "rk4  dt = 0.0001 s", "t = 0.250 s"}));
  EXPECT_EQ(overlay_time_line(2.0 / 3.0), "t = 0.667 s");
}

TEST(OverlayText, MarksAWrongFrameWithItsVerdictOnePhraseALine) {
  RenderFrame frame;
  mark_wrong(frame, "WRONG: projected on 44% of steps, strain 1.7");
  EXPECT_EQ(frame.banner, (std::vector<std::string>{"WRONG", "projected on 44% of steps", "strain 1.7"}));
}

TEST(OverlayText, TheCostLineIsWorkPerSimulatedSecondWithCpuOnlyWhenAsked) {
  EXPECT_EQ(cost_line(5000.0, 0.07, 0.5, false), "10k passes/sim s");
  EXPECT_EQ(cost_line(5000.0, 0.07, 0.5, true), "10k passes/sim s  140 ms cpu/sim s");
  EXPECT_EQ(cost_line(2.5e6, 0.0, 1.0, false), "2.5M passes/sim s");
  EXPECT_EQ(cost_line(0.0, 0.0, 0.0, true), "0 passes") << "at t = 0 there is no rate yet";
}

}  // namespace
}  // namespace clothsim::clip
