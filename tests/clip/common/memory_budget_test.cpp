// --max-memory: sizes as users write them, and a run over the limit refused with its estimate
// (exit 2, one line) before anything large exists.
#include "clip/common/memory_budget.h"

#include <gtest/gtest.h>

#include <fstream>

#include "cli/cli_process.h"
#include "cli/usage_error.h"
#include "scene/scene_parser.h"

namespace clothsim::testing {
namespace {

using clip::MemoryBudget;
using clip::parse_memory_size;

TEST(ParseMemorySize, ReadsBytesAndBinaryUnitsInTheUsualSpellings) {
  EXPECT_EQ(parse_memory_size("2000000000"), 2e9);
  EXPECT_EQ(parse_memory_size("512M"), 512.0 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("4G"), 4.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("4GB"), 4.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("4GiB"), 4.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("1.5g"), 1.5 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("64k"), 64.0 * 1024);
  for (const char* bad : {"", "G", "-1G", "0", "4X", "4 G", "nan", "inf", "1e999"})
    EXPECT_FALSE(parse_memory_size(bad).has_value()) << bad;
}

TEST(FormatBytes, GivesThreeDigitsSoTheOverflowShows) {
  EXPECT_EQ(clip::format_bytes(80.0 * 1024 * 1024), "80 MB");
  EXPECT_EQ(clip::format_bytes(2.01 * 1024 * 1024 * 1024), "2.01 GB");
  EXPECT_EQ(clip::format_bytes(512), "512 B");
}

TEST(MemoryBudget, RefusesOverTheLimitListingEveryPart) {
  MemoryBudget budget;
  budget.add("model", 1e9);
  budget.add("rk4", 5e8);
  EXPECT_EQ(usage_error([&] { budget.check("s.yaml", 4e9); }), "");
  const std::string refused = usage_error([&] { budget.check("s.yaml", 1e9); });
  EXPECT_EQ(refused.rfind("s.yaml: needs an estimated 1.48 GB (process 80 MB, model 954 MB, rk4 477 MB), "
                          "more than --max-memory 954 MB",
                          0),
            0u)
      << refused;
  EXPECT_GT(clip::default_memory_limit(), 0.0);
}

TEST(CmdRun, ARunOverMaxMemoryIsRefusedWithTheEstimateAndWritesNothing) {
  const std::string dir = scratch_dir("max_memory_run");
  const CliResult r = run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--set",
                                    "cloth.particles=[512,512]", "--integrator", "implicit_euler",
                                    "--max-memory", "256M", "--state", dir + "/s.csv"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("needs an estimated"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("implicit_euler"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("more than --max-memory 256 MB"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {}));
  EXPECT_EQ(run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--duration", "0.01",
                          "--max-memory", "256M"})
                .exit_code,
            0)
      << "the 25 x 25 drape fits";
}

// yaml-cpp holds a scene's whole node tree, about half a kilobyte a node: a scene file of
// 40,000 keyframes (1.7 MB) would take about 170 MB to parse, refused from its text first.
TEST(CmdRun, ASceneFileTooLargeToParseIsRefusedBeforeParsing) {
  const std::string dir = scratch_dir("max_memory_parse");
  std::string text = "cloth: {particles: [4, 4], springs: {structural: {}}}\nspheres:\n  - center: [0, 0, 0]\n"
                     "    radius: 1.0\n    kinematic: true\n    motion:\n";
  for (int i = 0; i < 40000; ++i) text += "      - {t: " + std::to_string(1.0 + i * 1e-5) + ", velocity: [0, 0, 5]}\n";
  const std::string scene = dir + "/long.yaml";
  std::ofstream(scene) << text;
  for (const char* command : {"validate", "run", "bench", "stability"}) {
    const CliResult r = run_clothsim({command, scene, "--max-memory", "150M"});
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(scene + ": needs an estimated"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("YAML tree (320"), std::string::npos) << r.err;  // 8 nodes a keyframe
    EXPECT_NE(r.err.find("more than --max-memory 150 MB; shorten the scene file"), std::string::npos) << r.err;
  }
}

// Under ulimit -v (RLIMIT_AS, set in the child's shell) Mesa crashed while creating a context
// or building shaders: below the context's needs the run is refused before any GL call, and a
// framebuffer that would not fit is refused before it is made. One line, exit 1, no file: said
// by the memory estimate when the whole run cannot fit (what it has), else by the renderer.
bool said_address_space(const std::string& err, const std::string& renderer_words) {
  return err.find("more than the address-space limit (ulimit -v") != std::string::npos ||
         err.find(renderer_words) != std::string::npos;
}

TEST(CmdRun, AnAddressSpaceLimitTooSmallForGlIsOneLineNotACrash) {
  const std::string dir = scratch_dir("gl_address_space");
  const std::string scene = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";
  for (const char* gl : {"egl", "osmesa"}) {
    for (const char* limit : {"400000", "700000"}) {
      const CliResult r = run_clothsim({"run", scene, "--still", "0.01", "-o", dir + "/s.png", "--gl", gl},
                                       std::string("ulimit -v ") + limit + ";");
      EXPECT_EQ(r.exit_code, 1) << gl << " " << limit << ": " << r.err;
      EXPECT_EQ(line_count(r.err), 1) << r.err;
      EXPECT_TRUE(said_address_space(r.err, "leaves too little for an OpenGL context")) << r.err;
    }
    const CliResult big = run_clothsim({"run", scene, "--still", "0.01", "-o", dir + "/s.png", "--gl", gl, "--width",
                                        "8192", "--height", "8192"},
                                       "ulimit -v 1500000;");
    EXPECT_EQ(big.exit_code, 1) << big.err;
    EXPECT_EQ(line_count(big.err), 1) << big.err;
    EXPECT_TRUE(said_address_space(big.err, "leaves too little for the 8192x8192 framebuffer")) << big.err;
  }
  EXPECT_TRUE(only_files(dir, {}));
}

TEST(CmdCompare, AHugePictureIsRefusedWithTheEncodersShare) {
  // The largest picture --width/--height allow (8192 x 8192): its encoder alone is 7.27 GB.
  const CliResult r = run_clothsim({"compare", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--width",
                                    "8192", "--height", "8192", "--video", "/tmp/never.mp4", "--max-memory", "1G"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("encoder 7.27 GB"), std::string::npos) << r.err;
}

TEST(CmdCompare, TheEstimateNamesThePositionsTheReferenceHoldsForTheLanes) {
  const CliResult r = run_clothsim({"compare", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--set",
                                    "cloth.particles=[512,512]", "--integrators", "rk4@20,symplectic_euler",
                                    "--duration", "0.5", "--width", "320", "--height", "180", "--video",
                                    "/tmp/never.mp4", "--max-memory", "256M"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("reference positions at the lanes' times 288 MB"), std::string::npos) << r.err;
}

TEST(Cli, MaxMemoryThatIsNotASizeIsBadUsage) {
  const CliResult r = run_clothsim({"validate", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--max-memory", "12X"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--max-memory: '12X' is not a size"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace clothsim::testing
