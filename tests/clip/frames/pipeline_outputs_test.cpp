// The outputs of the frame pipeline (src/clip/frames/pipeline_outputs.h): the lanes' tile labels.
#include "clip/frames/pipeline_outputs.h"

#include <gtest/gtest.h>

using namespace clothsim;
using namespace clothsim::clip;

namespace {

std::vector<Lane> course_lanes() {
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
  // The fixed point's is still too long: the grid shortens its name, keeping its step.
  EXPECT_EQ(labels[1], "implicit_euler_fixed_point@0.0001");
  EXPECT_EQ(narrow.shown_labels(labels)[1], "implicit_euler...@0.0001");
}

TEST(LaneTileLabels, LanesDifferingOnlyInTheirStepOrNameEndShowDistinctLabelsThatFitAtEveryWidth) {
  // Shortened with the step cut first, two symplectic lanes read "symplectic_e..." in both tiles
  // of a 200x120 compare; the course's fixed point lost its step at 320x180.
  const std::vector<std::vector<Lane>> cases{
      parse_lanes("symplectic_euler@1e-4,symplectic_euler@2e-4,implicit_euler@1/60,midpoint", "", 1e-4),
      parse_lanes("rk4@1e-4,rk4@4e-4,rk4@1/600", "", 1e-3),
      parse_lanes("course,implicit_euler", "", 1e-4),  // the same step, names with one start
  };
  for (const std::vector<Lane>& lanes : cases)
    for (const char* layout : {"auto", "Nx1"})
      for (int width : {200, 240, 320, 400, 640, 1280}) {
        const int n = static_cast<int>(lanes.size());
        const TileGrid grid = TileGrid::fit(parse_layout(layout, n), width, width * 9 / 16);
        const std::vector<std::string> given = lane_tile_labels(lanes, grid);
        const std::vector<std::string> shown = grid.shown_labels(given);
        const int scale = grid.label_scale(given);
        ASSERT_EQ(shown.size(), lanes.size());
        for (std::size_t i = 0; i < shown.size(); ++i) {
          const std::string where = std::string(layout) + " at " + std::to_string(width) + " px: " + shown[i];
          EXPECT_TRUE(label_fits(shown[i], grid.cell_width(), scale)) << where;
          // (Distinct in tiles of 8 glyphs or more: at 47 px, "symp..." twice.)
          for (std::size_t j = i + 1; j < shown.size() && grid.cell_width() >= 57; ++j)
            EXPECT_NE(shown[i], shown[j]) << where;
          // Shortened, a label keeps its lane's step wherever two letters of the name fit beside
          // it (with one, "i...@0.0001" would be both implicit lanes: their names' ends are shown).
          const std::string step = "@" + lanes[i].step_text;
          if (shown[i] != given[i] && label_fits("xx..." + step, grid.cell_width(), scale)) {
            EXPECT_EQ(shown[i].substr(shown[i].size() - step.size()), step) << where;
          }
        }
      }
  // The case of the review: 98 px tiles.
  const TileGrid small = TileGrid::fit(GridLayout{2, 2}, 200, 120);
  ASSERT_EQ(small.cell_width(), 98);
  EXPECT_EQ(small.shown_labels(lane_tile_labels(cases[0], small)),
            (std::vector<std::string>{"symplec...@1e-4", "symplec...@2e-4", "implici...@1/60", "midpoint@0.0001"}));
}
