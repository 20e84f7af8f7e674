// The look of the pictures: options resolved against the scene, bad values refused.
#include "clip/frames/picture_options.h"

#include <gtest/gtest.h>

#include "cli/usage_error.h"

using namespace clothsim;
using namespace clothsim::clip;
using clothsim::testing::usage_error;

namespace {
const std::vector<Lane> kLanes{Lane{IntegratorKind::Rk4, 1e-4, "1e-4"}};
}

TEST(PictureOptions, CompareColoursByErrorByDefaultAndRunByTheChecker) {
  SceneDef scene;
  const PictureLook compare = resolve_picture_look({}, scene, kLanes, true);
  EXPECT_EQ(compare.color, FieldKind::Error);
  ASSERT_TRUE(compare.reference);
  EXPECT_EQ(compare.reference->dt, 2.5e-5);
  EXPECT_EQ(resolve_picture_look({}, scene, kLanes, false).color, FieldKind::None);
  scene.render.color = "strain";  // the scene's key wins over the command's default
  EXPECT_EQ(resolve_picture_look({}, scene, kLanes, true).color, FieldKind::Strain);
  PictureOptions o;
  o.color = "speed";  // and the option over the key
  EXPECT_EQ(resolve_picture_look(o, scene, kLanes, true).color, FieldKind::Speed);
}

TEST(PictureOptions, ComparesEnergyInsetHasAReferenceWhateverTheColouringAndRunsHasNone) {
  SceneDef scene;
  PictureOptions o;
  o.color = "checker";
  o.inset = "energy";
  const PictureLook compare = resolve_picture_look(o, scene, kLanes, true);
  ASSERT_TRUE(compare.reference) << "E - Eref needs a reference lane";
  EXPECT_EQ(compare.reference->dt, 2.5e-5);
  EXPECT_FALSE(resolve_picture_look(o, scene, kLanes, false).reference) << "run's inset is E - E(0)";
  o.reference = "rk4@1e-5";
  EXPECT_EQ(resolve_picture_look(o, scene, kLanes, true).reference->dt, 1e-5);
  EXPECT_NE(usage_error([&] { resolve_picture_look(o, scene, kLanes, false); }).find("--reference goes with --color error"),
            std::string::npos);
}

TEST(PictureOptions, OverlayCameraInsetAndRange) {
  SceneDef scene;
  scene.render.overlay = "label";
  scene.render.camera_auto = true;
  PictureOptions o;
  PictureLook look = resolve_picture_look(o, scene, kLanes, false);
  EXPECT_EQ(look.overlay, OverlayMode::Label);
  EXPECT_TRUE(look.camera_auto);
  EXPECT_FALSE(look.overlay_cpu);
  EXPECT_FALSE(look.inset_energy);
  o.overlay = "none";
  o.camera = "scene";
  o.overlay_cost = "cpu";
  o.inset = "energy";
  o.color = "error";
  o.color_range = "1e-6,1e-2";
  look = resolve_picture_look(o, scene, kLanes, false);
  EXPECT_EQ(look.overlay, OverlayMode::None);
  EXPECT_FALSE(look.camera_auto);
  EXPECT_TRUE(look.overlay_cpu);
  EXPECT_TRUE(look.inset_energy);
  ASSERT_TRUE(look.color_range);
  EXPECT_EQ(look.color_range->lo, 1e-6);
  EXPECT_EQ(look.color_range->hi, 1e-2);
}

TEST(PictureOptions, EachBadValueIsRefusedNamingTheOption) {
  const SceneDef scene;
  const auto refused = [&](PictureOptions o) { return usage_error([&] { resolve_picture_look(o, scene, kLanes, true); }); };
  PictureOptions o;
  o.color = "rainbow";
  EXPECT_NE(refused(o).find("--color: unknown colouring 'rainbow'"), std::string::npos) << refused(o);
  // The last four lie past single precision, where the colour bar is drawn.
  for (const char* bad : {"1e-2", "1e-2,1e-6", "0,1", "a,b", "1,2,3", "-1,1", "1e-300,1e300", "1e-10,1e31",
                          "1,1.0000000000000002", "1e-40,1"}) {
    o = {};
    o.color_range = bad;
    EXPECT_EQ(refused(o).rfind("--color-range: ", 0), 0u) << bad << ": " << refused(o);
  }
  o = {};
  o.color = "checker";
  o.color_range = "1e-6,1e-2";
  EXPECT_NE(refused(o).find("--color-range goes with"), std::string::npos);
  o = {};
  o.color = "strain";
  o.reference = "rk4@1e-5";
  EXPECT_NE(refused(o).find("--reference goes with --color error"), std::string::npos);
  o = {};
  o.reference = "verlet";
  EXPECT_NE(refused(o).find("--reference: unknown integrator"), std::string::npos);
  o = {};
  o.camera = "orbit";
  EXPECT_NE(refused(o).find("--camera: expected auto or scene"), std::string::npos);
  o = {};
  o.overlay = "some";
  EXPECT_NE(refused(o).find("--overlay: expected full, label or none"), std::string::npos);
  o = {};
  o.overlay_cost = "wall";
  EXPECT_NE(refused(o).find("--overlay-cost: expected work or cpu"), std::string::npos);
  o = {};
  o.inset = "momentum";
  EXPECT_NE(refused(o).find("--inset: expected energy or none"), std::string::npos);
}
