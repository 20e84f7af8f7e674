// The frame pipeline's pieces that are not a command: overlay text and the colour scale; and a
// pipeline run through, for what a lane that diverged shows: its tile holds the last sane frame,
// captioned, and a contact sheet says it once in a wide cell instead of repeating the picture.
#include "clip/frames/frame_decoration.h"
#include "clip/frames/frame_pipeline.h"

#include <cmath>

#include <gtest/gtest.h>

#include "cli/cli_process.h"
#include "clip/frames/pipeline_outputs.h"
#include "core/model/stiffness_estimate.h"
#include "core/run/work_units.h"
#include "render/png_io.h"
#include "test_support.h"

using namespace clothsim;
using namespace clothsim::clip;

TEST(LaneOverlay, IsDeterministicUnlessCpuIsAskedForAndFollowsTheMode) {
  Model model;
  model.name = "drape";
  const Lane lane{IntegratorKind::Rk4, 1e-4, "1e-4"};
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

namespace {

// symplectic Euler at 1 ms runs on it, explicit Euler at 10 ms diverges at t = 0.19 s.
const char* const kSheet = clothsim::testing::kCornerSheet;

// Keeps lane `lane`'s picture and frame at every clip frame, and what it was told of the lane.
class KeepLane final : public FrameOutput {
 public:
  explicit KeepLane(std::size_t lane) : lane_(lane) {}
  std::string what() const override { return "keep"; }
  void on_target(const Target& target, const std::vector<LaneView>& lanes) override {
    if (target.frame < 0) return;
    pictures.push_back(*lanes[lane_].image);
    frames.push_back(*lanes[lane_].frame);
    limits.push_back(lanes[lane_].predicted_limit);
  }
  void finish() override {}
  void abandon(std::vector<std::string>&, std::vector<std::string>&) override {}
  std::vector<Image> pictures;
  std::vector<LaneFrame> frames;
  std::vector<double> limits;
 private:
  std::size_t lane_;
};

struct DivergedRun {
  std::vector<Image> pictures;
  std::vector<LaneFrame> frames;
  std::vector<double> limits;
};

// symplectic_euler@1e-3 beside explicit_euler@1e-2 at 20 frames/s to 1.5 s, 64 x 48 tiles;
// `sheet`: also a contact sheet at 0.1, 0.5, 1 and 1.5 s written there.
DivergedRun run_diverging_pair(OverlayMode overlay, const std::string& sheet = "") {
  const SceneDef scene = parse_scene(kSheet, "inline.yaml");
  const Model model = build_model(scene);
  const TargetPlan plan(1.5, 20.0, true, sheet.empty() ? std::vector<double>{} : std::vector<double>{0.1, 0.5, 1.0, 1.5});
  PipelineConfig c;
  c.rendering = true;
  c.width = 64;
  c.height = 48;
  c.tiles = true;
  c.overlay = overlay;
  c.samples = 1;
  c.scene_render = scene.render;
  Renderer renderer;
  const std::vector<Lane> lanes{Lane{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"},
                                    Lane{IntegratorKind::ExplicitEuler, 1e-2, "1e-2"}};
  FramePipeline pipeline(model, plan, lanes, c, &renderer);
  auto keep = std::make_unique<KeepLane>(1);
  KeepLane* kept = keep.get();
  pipeline.add(std::move(keep));
  if (!sheet.empty()) pipeline.add(make_sheet_output(sheet, {"symplectic", "explicit"}, {"a", "b", "c", "d"}, {}, 0, 0, false));
  pipeline.run("test");
  return {kept->pictures, kept->frames, kept->limits};
}

}  // namespace

TEST(FramePipeline, ADivergedTileHoldsItsLastSaneFramesPictureAndSaysItsPredictedStableStep) {
  const DivergedRun r = run_diverging_pair(OverlayMode::None);
  ASSERT_EQ(r.frames.size(), 31u);
  std::size_t first = 0;  // the first clip frame past the divergence
  while (first < r.frames.size() && !r.frames[first].divergence) ++first;
  ASSERT_GT(first, 1u) << "t = 0 and at least one more frame are sane";
  ASSERT_LT(first, r.frames.size()) << "explicit Euler at 10 ms diverges";
  EXPECT_NEAR(r.frames[first].divergence->t, 0.19, 1e-9);
  // Without an overlay the held picture is the last sane frame's render, pixel for pixel, to the end.
  const Image& sane = r.pictures[first - 1];
  EXPECT_FALSE(r.frames[first - 1].divergence);
  for (std::size_t k = first; k < r.pictures.size(); ++k) EXPECT_EQ(r.pictures[k].rgba, sane.rgba) << "frame " << k;
  EXPECT_NE(sane.rgba, r.pictures[0].rgba) << "the last sane frame, not the start";
  // What its caption says: the stiffness estimate's step for explicit Euler on this model.
  const double predicted = analysis::predicted_limit(analysis::estimate_stiffness(clothsim::testing::model_from_yaml(kSheet)),
                                                     IntegratorKind::ExplicitEuler);
  ASSERT_GT(predicted, 0.0);
  EXPECT_LT(predicted, 1e-2) << "the step that diverged is above it";
  EXPECT_EQ(r.limits[first], predicted);
  // With the overlay the held picture carries the caption: not the sane frame's picture.
  const DivergedRun full = run_diverging_pair(OverlayMode::Full);
  EXPECT_NE(full.pictures[first].rgba, full.pictures[first - 1].rgba);
}

TEST(FramePipeline, ASheetCollapsesADivergedLanesRowAfterItsHeldCellIntoOneCell) {
  // The lane diverges at 0.19 s: column b (0.5 s) holds its picture, c and d are one panel.
  const std::string dir = clothsim::testing::scratch_dir("pipeline_sheet_span");
  run_diverging_pair(OverlayMode::Full, dir + "/sheet.png");
  const Image sheet = read_png(dir + "/sheet.png");
  long panel = 0;  // pixels of the span's panel colour (contact_sheet.cpp)
  for (int y = 0; y < sheet.height; ++y)
    for (int x = 0; x < sheet.width; ++x) {
      const std::uint8_t* p = sheet.pixel(x, y);
      panel += p[0] == 44 && p[1] == 44 && p[2] == 50;
    }
  EXPECT_GT(panel, 2 * 64 * 48 * 7 / 10) << "two cells' room, less its text";
  EXPECT_LT(panel, 3 * 64 * 48) << "no more than the two cells and their gutter";
}
