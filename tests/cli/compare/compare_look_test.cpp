// What compare's pictures show: golden images of an error-coloured still and of a contact
// sheet with its colour bar, one colour bar per grid beside the tiles and none in them, and the
// default clip's framing (the cloth covers at least a quarter of each tile). CLOTHSIM_UPDATE_GOLDEN=1 rewrites the goldens after an intended change.
#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "cli/cli_process.h"
#include "clip/frames/grid_legend.h"
#include "clip/frames/picture_options.h"
#include "core/run/simulation.h"
#include "render/colormap.h"
#include "render/image_diff.h"
#include "render/png_io.h"
#include "render/renderer.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "render/video/tiling.h"
#include "view/snapshot.h"

namespace fs = std::filesystem;
using namespace clothsim;
namespace ct = clothsim::testing;

namespace {

const std::string kDrape = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";

bool updating_goldens() {
  const char* v = std::getenv("CLOTHSIM_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

// Makes `out` with compare and holds it to tests/golden/`name` (or rewrites that).
// (--overlay-cost work: the measured CPU time would differ from run to run.)
void expect_golden(std::vector<std::string> args, const std::string& out, const std::string& name) {
  args.insert(args.end(), {"--overlay-cost", "work"});
  const auto r = ct::run_clothsim(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string golden = std::string(CLOTHSIM_GOLDEN_DIR) + "/" + name;
  if (updating_goldens()) {
    fs::copy_file(out, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "rewrote " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing (CLOTHSIM_UPDATE_GOLDEN=1 writes it)";
  const Image expected = read_png(golden), actual = read_png(out);
  ASSERT_EQ(expected.width, actual.width);
  ASSERT_EQ(expected.height, actual.height);
  const DiffTolerance tolerance;
  const DiffStats stats = compare_images(expected, actual, tolerance.pixel_threshold);
  if (!within_tolerance(stats, tolerance)) {
    write_png(out + ".diff.png", diff_image(expected, actual));
    ADD_FAILURE() << out << " differs from " << golden << ": rms " << stats.rms << ", max " << stats.max
                  << "; see " << out << ".diff.png (if intended: CLOTHSIM_UPDATE_GOLDEN=1 ctest -R CompareLook)";
  }
}

// The columns of `image` that hold a stretch of colour-bar gradient: 24 rows or more one under
// the other, each exactly a colormap colour and their colours changing down the stretch (a bar's
// rows are unshaded colormap colours; the cloth's are lit, so a shaded cloth is no bar).
std::vector<int> bar_columns(const Image& image) {
  static const std::set<std::array<std::uint8_t, 3>> palette = [] {
    std::set<std::array<std::uint8_t, 3>> p;
    for (int k = 0; k <= 4096; ++k) p.insert(render::colormap_rgb8(static_cast<float>(k) / 4096.f));
    return p;
  }();
  std::vector<int> columns;
  for (int x = 0; x < image.width; ++x) {
    int run = 0;
    std::array<std::uint8_t, 3> first{};
    for (int y = 0; y < image.height; ++y) {
      const std::uint8_t* p = image.pixel(x, y);
      const std::array<std::uint8_t, 3> c{p[0], p[1], p[2]};
      if (!palette.count(c)) {
        run = 0;
        continue;
      }
      if (run++ == 0) first = c;
      if (run >= 24 && c != first) {
        columns.push_back(x);
        break;
      }
    }
  }
  return columns;
}

// How many colour bars `columns` (bar_columns) make: groups of adjacent columns.
int bar_count(const std::vector<int>& columns) {
  int groups = 0;
  for (std::size_t i = 0; i < columns.size(); ++i) groups += i == 0 || columns[i] != columns[i - 1] + 1;
  return groups;
}

std::vector<std::string> small_drape(const std::string& duration) {
  return {kDrape, "--set", "cloth.particles=[9,9]", "--duration", duration, "--width", "640", "--height", "360",
          "--color", "strain", "--quiet"};
}

}  // namespace

TEST(CompareLook, AGridDrawsOneColourBarInAStripBesideItsTilesAndNoneInThem) {
  // Four tiles coloured by strain, one of them diverged (rk4 at 4e-4 s blows up at 0.31 s and
  // holds its last picture, at the top of the scale).
  const std::string dir = ct::scratch_dir("compare_look_one_bar");
  std::vector<std::string> args = {"compare"};
  for (const std::string& a : small_drape("0.4")) args.push_back(a);
  args.insert(args.end(), {"--integrators", "explicit_euler,midpoint,rk4@4e-4,implicit_euler@1/60", "--still", "0.4",
                           "-o", dir + "/still.png", "--sheet", dir + "/sheet.png", "--times", "0.1,0.4"});
  const auto r = ct::run_clothsim(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Image still = read_png(dir + "/still.png"), sheet = read_png(dir + "/sheet.png");
  ASSERT_EQ(still.width, 640);
  ASSERT_EQ(sheet.width, 640) << "the strip comes out of the width asked for";
  const clip::LegendGrid grid = clip::fit_legend_grid(GridLayout{2, 2}, 640, 360, FieldKind::Strain);
  ASSERT_GT(grid.legend_width, 0);
  EXPECT_EQ(grid.width(), 640);
  const std::vector<int> in_still = bar_columns(still);
  EXPECT_EQ(bar_count(in_still), 1);
  for (int x : in_still) EXPECT_GE(x, grid.grid.width()) << "a bar column inside the tiles";
  const std::vector<int> in_sheet = bar_columns(sheet);
  EXPECT_EQ(bar_count(in_sheet), 1) << "one bar for the sheet's 8 cells";
  for (int x : in_sheet) EXPECT_GE(x, 640 - grid.legend_width) << "a bar column inside the cells";
}

TEST(CompareLook, APictureTooNarrowForTheTilesAndTheStripIsRefusedInOneLine) {
  const std::string dir = ct::scratch_dir("compare_look_narrow");
  std::vector<std::string> args = {"compare", kDrape, "--set", "cloth.particles=[9,9]", "--duration", "0.1", "--width",
                                   "40", "--height", "40", "--color", "strain", "--still", "0.1", "-o", dir + "/s.png"};
  const auto r = ct::run_clothsim(args);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(ct::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("colour bar's"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/s.png"));
  args[11] = "checker";  // no bar, no strip: the tiles have the whole width
  EXPECT_EQ(ct::run_clothsim(args).exit_code, 0);
}

TEST(CompareLook, TheBarDetectorFindsTheBarInARunsPicture) {
  // run draws its one picture with the bar over it: the detector above sees it there.
  const std::string dir = ct::scratch_dir("compare_look_run_bar");
  std::vector<std::string> args = {"run"};
  for (const std::string& a : small_drape("0.1")) args.push_back(a);
  args.insert(args.end(), {"--still", "0.1", "-o", dir + "/run.png"});
  const auto r = ct::run_clothsim(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<int> columns = bar_columns(read_png(dir + "/run.png"));
  EXPECT_EQ(bar_count(columns), 1);
  ASSERT_FALSE(columns.empty());
  EXPECT_LT(columns.back(), 640);
}

TEST(CompareLook, AnErrorColouredStillMatchesItsGolden) {
  // The default colouring: error against RK4 at a quarter of the step, its scale from the data.
  // explicit_euler's tile says UNRESOLVED under its reference line, as the table does (its
  // error is under 10x the reference's: it was drawn as a plain error map, issue #51).
  const std::string dir = ct::scratch_dir("compare_look_still");
  expect_golden({"compare", kDrape, "--set", "cloth.particles=[9,9]", "--duration", "0.3", "--width", "640",
                 "--height", "360", "--integrators", "explicit_euler,rk4", "--still", "0.3", "-o", dir + "/still.png"},
                dir + "/still.png", "compare_error_still.png");
}

TEST(CompareLook, ASheetWithAColourBarMatchesItsGolden) {
  const std::string dir = ct::scratch_dir("compare_look_sheet");
  expect_golden({"compare", kDrape, "--set", "cloth.particles=[9,9]", "--duration", "0.3", "--width", "640",
                 "--height", "360", "--integrators", "symplectic_euler@1e-4,symplectic_euler@1e-3", "--color", "strain",
                 "--color-range", "1e-5,1e-2", "--sheet", dir + "/sheet.png", "--times", "0.1,0.3"},
                dir + "/sheet.png", "compare_strain_sheet.png");
}

TEST(CompareLook, TilesAreSmoothedByFxaaUnlessTheSceneOrTheOptionSaysOtherwise) {
  const std::string dir = ct::scratch_dir("compare_look_antialias");
  const auto still = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"compare", kDrape, "--set", "cloth.particles=[9,9]", "--duration", "0.1",
                                     "--width", "320", "--height", "180", "--integrators", "symplectic_euler",
                                     "--color", "checker", "--overlay-cost", "work", "--still", "0.1", "-o",
                                     dir + "/" + name + ".png"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = ct::run_clothsim(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_png(dir + "/" + name + ".png").rgba;
  };
  const auto by_default = still("default", {});
  EXPECT_EQ(by_default, still("fxaa", {"--antialias", "fxaa"}));
  const auto msaa = still("msaa", {"--antialias", "msaa"});
  EXPECT_NE(by_default, msaa);
  EXPECT_EQ(msaa, still("scene_msaa", {"--set", "render.msaa=4"}));  // a sample count in the scene says msaa
  EXPECT_NE(msaa, still("none", {"--antialias", "none"}));
  const auto bad = ct::run_clothsim({"compare", kDrape, "--antialias", "smaa", "--still", "0", "-o", dir + "/bad.png"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--antialias: expected msaa, fxaa or none, got 'smaa'"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir + "/bad.png"));
}

TEST(CompareLook, TheDefaultClipsClothCoversAQuarterOfEachTile) {
  // The default clip's tiles: 1280x720 in a 2x2 grid. The cloth's pixels are those that
  // differ from the same frame without the cloth (no shadows, so only the cloth counts).
  const SceneDef scene = load_scene(kDrape);
  ASSERT_TRUE(scene.render.camera_auto) << "the shipped drape is framed automatically";
  const TileGrid grid = clothsim::clip::fit_legend_grid(GridLayout{2, 2}, scene.render.width, scene.render.height,
                                                       FieldKind::Error).grid;  // the tiles left of the colour bar
  const Model model = build_model(scene);
  const RenderCamera camera = clothsim::clip::auto_camera(model, scene.render, static_cast<double>(grid.cell_width()) / grid.cell_height());
  Renderer renderer;
  clothsim::Run run(model, IntegratorKind::SymplecticEuler, model.dt);
  for (const double t : {0.0, 1.0, 2.5, 5.0}) {
    ASSERT_TRUE(run.advance_to(t));
    RenderFrame with = make_render_frame(model, run.state(), scene.render);
    with.width = grid.cell_width();
    with.height = grid.cell_height();
    with.camera = camera;
    with.shadows = false;
    RenderFrame without = with;
    without.cloth_triangles.clear();
    const Image a = renderer.render(with), b = renderer.render(without);
    long cloth = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        cloth += !std::equal(a.pixel(x, y), a.pixel(x, y) + 3, b.pixel(x, y));
    const double share = static_cast<double>(cloth) / (static_cast<double>(a.width) * a.height);
    EXPECT_GE(share, 0.25) << "t = " << t << " s: the cloth covers " << 100 * share << " % of the tile";
    RecordProperty("cloth_share_t" + std::to_string(static_cast<int>(10 * t)), std::to_string(share));
  }
}
