// The outputs of the frame pipeline (tools/cli/pipeline_outputs.h): the lanes' tile labels.
#include "pipeline_outputs.h"

#include <gtest/gtest.h>

using namespace clothsim;
using namespace clothsim::cli;

namespace {

std::vector<LaneSpec> course_lanes() {
  return parse_lanes("course", "", 1e-4);  // explicit Euler, the fixed point, midpoint, RK4
}

}  // namespace

TEST(LaneTileLabels, NameTheStepInFullWhereEveryLabelFitsItsTile) {
  const TileGrid wide = TileGrid::fit(GridLayout{2, 2}, 1280, 720);  // 638 px tiles
  const std::vector<std::string> labels = lane_tile_labels(course_lanes(), wide);
  ASSERT_EQ(labels.size(), 4u);
  EXPECT_EQ(labels[0], "explicit_euler  dt = 0.0001 s");
  EXPECT_EQ(labels[1], "implicit_euler (fixed point)  dt = 0.0001 s");
  EXPECT_EQ(labels[3], "rk4  dt = 0.0001 s");
}

TEST(LaneTileLabels, SpellEveryLaneAsIntegratorsDoesWhereOneDoesNotFit) {
  // A 320x180 compare of four lanes: 158 px tiles hold 25 glyphs. "explicit_euler  dt = 0.0001 s"
  // (29) did not fit and ran into the gutter; every tile now reads NAME@STEP, one form for all.
  const TileGrid narrow = TileGrid::fit(GridLayout{2, 2}, 320, 180);
  ASSERT_EQ(narrow.cell_width(), 158);
  const std::vector<std::string> labels = lane_tile_labels(course_lanes(), narrow);
  ASSERT_EQ(labels.size(), 4u);
  EXPECT_EQ(labels[0], "explicit_euler@0.0001");
  EXPECT_EQ(labels[2], "midpoint@0.0001") << "the same form in every tile, though midpoint's full label fits";
  EXPECT_EQ(labels[3], "rk4@0.0001");
  for (std::size_t i : {0u, 2u, 3u}) EXPECT_TRUE(label_fits(labels[i], 158, 1)) << labels[i];
  // The fixed point's is still too long: the grid shortens it, keeping the integrator's name.
  EXPECT_EQ(labels[1], "implicit_euler (fixed point)@0.0001");
  EXPECT_EQ(fit_label(labels[1], 158, 1), "implicit_euler (fixed...");
}
