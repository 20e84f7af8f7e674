// --export through the command line: refused before work on a bad path, one export per compare
// lane, a diverged run's files up to its end, a stopped run's files kept and named.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {
namespace fs = std::filesystem;

std::string shipped(const std::string& name) { return std::string(CLOTHSIM_SCENES_DIR) + "/" + name; }

std::int32_t pc2_samples(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char header[32] = {};
  in.read(header, sizeof header);
  std::int32_t samples = 0;
  std::memcpy(&samples, header + 28, 4);
  return samples;
}

TEST(ExportOption, ABadPathIsRefusedBeforeAnyWorkAndNothingIsWritten) {
  const std::string dir = scratch_dir("export_bad");
  for (const std::string& bad :
       std::vector<std::string>{dir + "/c.stl", dir + "/f.obj", dir + "/f_%05d_%05d.ply", dir + "/c_%03d.pvd"}) {
    const CliResult r = run_clothsim({"run", shipped("drape.yaml"), "--metrics", dir + "/m.csv", "--export", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_EQ(r.err.rfind("clothsim: --export: " + bad + ": ", 0), 0u) << r.err;
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(ExportOption, NoOverwriteKeepsAnExistingCacheAndSeries) {
  const std::string dir = scratch_dir("export_keep");
  std::ofstream(dir + "/c.obj") << "mine";
  CliResult r = run_clothsim({"run", shipped("spring.yaml"), "-n", "--export", dir + "/c.pc2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "clothsim: --export: " + dir + "/c.obj exists, and -n/--no-overwrite keeps it\n");
  fs::create_directories(dir + "/seq");
  std::ofstream(dir + "/seq/f_sphere0_007.ply") << "mine";
  r = run_clothsim({"run", shipped("drape.yaml"), "-n", "--export", dir + "/seq/f_%03d.ply"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("already holds f_sphere0_007.ply"), std::string::npos) << r.err;
}

TEST(ExportOption, CompareWritesOneCachePerLaneNamedByItsDirectory) {
  const std::string dir = scratch_dir("export_compare");
  const CliResult r = run_clothsim({"compare", shipped("drape.yaml"), "--integrators", "rk4@4e-4,rk4@2e-4,midpoint",
                                    "--match", "none", "--duration", "0.1", "--export", dir + "/c.pc2", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string& lane : std::vector<std::string>{"rk4@4e-4", "rk4@2e-4", "midpoint"}) {
    EXPECT_EQ(pc2_samples(dir + "/c." + lane + ".pc2"), 4) << lane;  // t = 0, 1/30, 2/30, 3/30
    EXPECT_TRUE(fs::exists(dir + "/c." + lane + ".obj")) << lane;
    EXPECT_EQ(pc2_samples(dir + "/c." + lane + ".sphere0.pc2"), 4) << lane;
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 12);  // no temporaries
}

TEST(ExportOption, ARunThatDivergesExportsEveryFrameUpToItsLastFiniteState) {
  const std::string dir = scratch_dir("export_diverged");
  const CliResult r = run_clothsim({"run", shipped("stiff.yaml"), "--integrator", "explicit_euler", "--duration", "1",
                                    "--fps", "10", "--export", dir + "/p.pvd", "--quiet"});
  ASSERT_EQ(r.exit_code, 3) << r.err;
  // Diverges at about 0.25 s: frames 0, 0.1 and 0.2 s and the last finite state's, indexed.
  std::ifstream in(dir + "/p.pvd");
  std::stringstream text;
  text << in.rdbuf();
  const std::string pvd = text.str();
  EXPECT_NE(pvd.find("timestep=\"0.20000000000000001\" group=\"\" part=\"0\" file=\"p/cloth_00002.vtp\""),
            std::string::npos) << pvd;
  EXPECT_NE(pvd.find("file=\"p/cloth_00003.vtp\""), std::string::npos);
  EXPECT_EQ(pvd.find("file=\"p/cloth_00004.vtp\""), std::string::npos);
  EXPECT_TRUE(only_files(dir + "/p", {"cloth_00000.vtp", "cloth_00001.vtp", "cloth_00002.vtp", "cloth_00003.vtp",
                                      "sphere0_00000.vtp", "sphere0_00001.vtp", "sphere0_00002.vtp",
                                      "sphere0_00003.vtp"}));
}

TEST(ExportOption, AStoppedRunKeepsTheFramesWrittenAndNamesThem) {
  const std::string dir = scratch_dir("export_stopped");
  const StoppedResult r = run_clothsim_interrupted(
      {"run", shipped("drape.yaml"), "--integrator", "rk4", "--dt", "1e-5", "--export", dir + "/f_%05d.obj",
       "--quiet"},
      1.5);
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_NE(r.err.find("OBJ files in " + dir + "/"), std::string::npos) << r.err;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_NE(entry.path().filename().string()[0], '.') << entry.path();  // complete files only
}

}  // namespace
}  // namespace clothsim::testing
