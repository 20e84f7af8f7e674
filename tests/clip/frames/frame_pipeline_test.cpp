// The frame pipeline's pieces that are not a command: overlay text and the colour scale.
#include "clip/frames/frame_decoration.h"
#include "clip/frames/frame_pipeline.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/work_units.h"

using namespace clothsim;
using namespace clothsim::clip;

TEST(LaneOverlay, IsDeterministicUnlessCpuIsAskedForAndFollowsTheMode) {
  Model model;
  model.name = "drape";
  const LaneSpec lane{IntegratorKind::Rk4, 1e-4, "1e-4"};
  LaneFrame f;
  f.t = 0.5;
  f.totals.force_evals = 20000;
  f.totals.cpu_seconds = 0.123;
  EXPECT_EQ(lane_overlay(model, lane, f, OverlayMode::Full, false, false),
            (std::vector<std::string>{"t = 0.500 s", "40k passes/sim s"}))
      << "a tile: the grid labels it with the lane";
  EXPECT_EQ(lane_overlay(model, lane, f, OverlayMode::Full, true, false),
            (std::vector<std::string>{"drape", "rk4  dt = 1e-4 s", "t = 0.500 s", "40k passes/sim s"}));
  EXPECT_EQ(lane_overlay(model, lane, f, OverlayMode::Full, false, true).back(), "40k passes/sim s  246 ms cpu/sim s");
  // An implicit lane's Newton work counts (core/work_units.h): not its force evaluations alone.
  LaneFrame implicit = f;
  implicit.totals.force_evals = 1000;
  implicit.totals.assemblies = 1000;
  implicit.totals.cg_iterations = 3000;
  EXPECT_GT(spring_passes(implicit.totals), 2.0 * 1000 + 3000);
  EXPECT_EQ(lane_overlay(model, lane, f, OverlayMode::Label, true, false), (std::vector<std::string>{"rk4  dt = 1e-4 s"}));
  EXPECT_TRUE(lane_overlay(model, lane, f, OverlayMode::Label, false, false).empty());
  EXPECT_TRUE(lane_overlay(model, lane, f, OverlayMode::None, true, true).empty());
}

TEST(RangeFromData, RoundsTheLargestValueUpToADecadeAndSpansFourDecadesForTheError) {
  const std::vector<float> a{0.f, 3e-4f, 2e-6f}, b{0.02f, std::numeric_limits<float>::infinity(), -1.f};
  const auto error = range_from_data({&a, &b}, FieldKind::Error);
  ASSERT_TRUE(error);
  EXPECT_DOUBLE_EQ(error->hi, 0.1);
  EXPECT_DOUBLE_EQ(error->lo, 1e-5);
  const auto strain = range_from_data({&a}, FieldKind::Strain);
  ASSERT_TRUE(strain);
  EXPECT_NEAR(strain->hi, 1e-3, 1e-18);
  EXPECT_NEAR(strain->lo, 1e-6, 1e-21);
  const std::vector<float> zeros(5, 0.f);
  EXPECT_FALSE(range_from_data({&zeros}, FieldKind::Speed)) << "a cloth at rest has no scale";
}

TEST(EnergyInset, ShowsTheChangeSinceTheStartOnSharedAxesAnExplodingLaneCannotFlatten) {
  std::vector<EnergyHistory> lanes(3);
  for (int k = 0; k <= 10; ++k) {
    lanes[0].add(0.1 * k, 100.0 - k);               // a damped lane: 100 -> 90 J
    lanes[1].add(0.1 * k, 100.0 + 0.5 * k);         // a gaining one: 100 -> 105 J
    lanes[2].add(0.1 * k, 100.0 * std::pow(10, k));  // an exploding one
  }
  RenderFrame f;
  draw_energy_inset(f, lanes, 0, 1.0);
  ASSERT_TRUE(f.inset.show);
  EXPECT_EQ(f.inset.label, "E-E(0) [J]");
  ASSERT_EQ(f.inset.value.size(), 11u);
  EXPECT_FLOAT_EQ(f.inset.value.front(), 0.f);
  EXPECT_FLOAT_EQ(f.inset.value.back(), -10.f);
  EXPECT_FLOAT_EQ(f.inset.v_lo, -10.f) << "the data's own low end";
  EXPECT_FLOAT_EQ(f.inset.v_hi, 200.f) << "2 |E(0)| above the start, not 1e12";
  EXPECT_FLOAT_EQ(f.inset.t_hi, 1.f);
  RenderFrame g;
  draw_energy_inset(g, lanes, 1, 1.0);
  EXPECT_FLOAT_EQ(g.inset.value.back(), 5.f) << "the gain reads apart from the loss";
  EXPECT_EQ(g.inset.v_hi, f.inset.v_hi) << "one axis for every tile";
  EXPECT_EQ(g.inset.v_lo, f.inset.v_lo);
}

TEST(EnergyInset, AgainstAReferenceShowsWhatEachLaneGainsOrLosesBeyondItAndStopsWhereItDoes) {
  // The reference loses 20 J a second to its dampers; one lane loses more (numerical damping),
  // one less, sampled at other times; one blew up and was declared diverged.
  EnergyHistory reference;
  for (int k = 0; k <= 8; ++k) reference.add(0.1 * k, 100.0 - 2.0 * k);  // to t = 0.8 s only
  std::vector<EnergyHistory> lanes(3);
  for (int k = 0; k <= 10; ++k) {
    lanes[0].add(0.1 * k, 100.0 - 3.0 * k);
    lanes[1].add(0.1 * k + 0.05, 99.0 - 1.5 * k);  // between the reference's samples
    lanes[2].add(0.1 * k, 100.0 * std::pow(10, k));
  }
  const std::vector<bool> diverged{false, false, true};
  RenderFrame f, g;
  draw_energy_inset(f, lanes, 0, 1.0, &reference, diverged);
  draw_energy_inset(g, lanes, 1, 1.0, &reference, diverged);
  EXPECT_EQ(f.inset.label, "E-Eref [J]");
  ASSERT_EQ(f.inset.value.size(), 9u) << "no point past the reference's last sample";
  EXPECT_NEAR(f.inset.value.back(), -8.f, 1e-4f) << "100 - 24 against 100 - 16";
  ASSERT_EQ(g.inset.value.size(), 8u);
  EXPECT_NEAR(g.inset.value.front(), 0.f, 1e-4f) << "the reference interpolated at 0.05 s: 99";
  EXPECT_NEAR(g.inset.value.back(), 3.5f, 1e-4f) << "at 0.75 s: 99 - 10.5 against 100 - 15";
  EXPECT_NEAR(f.inset.v_lo, -8.f, 1e-4f) << "the diverged lane sets no axis";
  EXPECT_NEAR(f.inset.v_hi, 3.5f, 1e-4f);
  EXPECT_EQ(g.inset.v_hi, f.inset.v_hi);
}
