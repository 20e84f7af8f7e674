// `clothsim bench --budget N` as users call it: the grid's CSV, the verdicts with their compare
// command, the frame rate it fills, and every refusal in one line with exit 2 and nothing written.
#include <gtest/gtest.h>

#include <fstream>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

std::string scene(const std::string& name) { return std::string(CLOTHSIM_SCENES_DIR) + "/" + name; }

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// A 5 x 5 drape for a tenth of a second: every solver at 1 x 2 and 2 x 1.
std::vector<std::string> small_drape(std::vector<std::string> more) {
  std::vector<std::string> args = {"bench", scene("drape.yaml"), "--set", "cloth.particles=[5,5]", "--duration", "0.1"};
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(CmdBenchBudget, WritesARowPerSplitAndAVerdictPerSolver) {
  const std::string dir = scratch_dir("bench_budget_csv");
  const CliResult r = run_clothsim(small_drape({"--budget", "2", "--csv", dir + "/budget.csv"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  // drape.yaml writes render.fps: 30, so the frame is 1/30 s and 0.1 s holds 3 of them.
  EXPECT_NE(r.out.find("at 30 frames/s (the scene's render.fps), T = 0.1 s (3 frames)"), std::string::npos) << r.out;
  for (const char* solver : {"xpbd", "vbd", "projective_dynamics", "implicit_euler"}) {
    EXPECT_NE(r.out.find(std::string("  ") + solver + " at N = 2: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(std::string("--integrators ") + solver + "@1/30:2," + solver + "@1/60:1 --set "),
              std::string::npos)
        << r.out;
  }
  const auto rows = lines(dir + "/budget.csv");
  ASSERT_EQ(rows.size(), 1u + 4u * 2u);
  EXPECT_EQ(rows[0].rfind("solver,lane,budget,substeps,iterations,dt,fps,duration,frames,steps,", 0), 0u) << rows[0];
  EXPECT_EQ(rows[1].rfind("xpbd,xpbd@1/30:2,2,1,2,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("xpbd,xpbd@1/60:1,2,2,1,", 0), 0u) << rows[2];
  EXPECT_EQ(rows[8].rfind("implicit_euler,implicit_euler@1/60:1,2,2,1,", 0), 0u) << rows[8];
  EXPECT_TRUE(only_files(dir, {"budget.csv"}));
}

TEST(CmdBenchBudget, FillsSixtyFramesASecondWhereTheSceneWritesNoRate) {
  // chain.yaml has no render.fps: Macklin's 60; --fps says otherwise.
  const CliResult r = run_clothsim({"bench", scene("chain.yaml"), "--budget", "2", "--duration", "0.05",
                                    "--integrators", "xpbd"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("at 60 frames/s (the default), T = 0.05 s (3 frames)"), std::string::npos) << r.out;
  const CliResult f = run_clothsim({"bench", scene("chain.yaml"), "--budget", "2", "--duration", "0.05",
                                    "--integrators", "xpbd", "--fps", "20"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_NE(f.out.find("at 20 frames/s (--fps), T = 0.05 s (1 frame)"), std::string::npos) << f.out;
}

TEST(CmdBenchBudget, LeavesOutTheDefaultSolversABarrierSceneCannotRun) {
  const CliResult r = run_clothsim({"bench", scene("drape_smooth.yaml"), "--set", "cloth.particles=[5,5]",
                                    "--duration", "0.1", "--budget", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("bench --budget: xpbd has no barrier contact"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bench --budget: projective_dynamics has no barrier contact"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("2 solvers x 1 splits"), std::string::npos) << r.out;
}

TEST(CmdBenchBudget, RefusesWhatDoesNotFitInOneLine) {
  const std::string dir = scratch_dir("bench_budget_refusals");
  const std::string csv = dir + "/budget.csv";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {small_drape({"--budget", "0"}), "--budget: 0 is not a whole number from 1 to 1000000"},
      {small_drape({"--budget", "1000001"}), "--budget: 1000001 is not a whole number from 1 to 1000000"},
      {small_drape({"--budget", "30", "--dts", "1e-3"}), "--budget: --dts sweeps steps"},
      {small_drape({"--budget", "30", "--vary", "ks=1e4,2e4"}), "--budget: --vary "},
      {small_drape({"--budget", "30", "--scale", "8,16"}), "--budget: --scale "},
      {small_drape({"--budget", "30", "--summary", dir + "/s.json"}), "--budget: --summary "},
      {small_drape({"--budget", "30", "--tols", "1e-4"}), "--budget: --tols sweeps an adaptive lane's tolerances"},
      {small_drape({"--budget", "30", "--error", "end"}), "--budget: --error chooses the step sweep's measure"},
      {small_drape({"--budget", "30", "--integrators", "rk4"}), "--integrators: 'rk4': not an iterative solver"},
      {small_drape({"--budget", "30", "--integrators", "xpbd:5"}), "--integrators: 'xpbd:5': --budget sets the iterations"},
      {small_drape({"--budget", "30", "--integrators", "vbd@1/60"}), "--integrators: 'vbd@1/60': --budget sets each step"},
      {small_drape({"--budget", "6", "--fps", "0"}), "--fps: must be > 0 and <= 1000"},
      {{"bench", scene("drape.yaml"), "--budget", "6", "--duration", "0.51"},
       "--duration: 0.51 s is not a whole number of frames at 30 frames/s"},
      {{"bench", scene("drape_smooth.yaml"), "--budget", "6", "--integrators", "xpbd"},
       "--integrators: collision.model: barrier: xpbd has no barrier contact"},
      {small_drape({"--fps", "60"}), "--fps: the frame of --budget; give --budget N with it"},
  };
  for (const auto& [args, message] : cases) {
    std::vector<std::string> with_csv = args;
    with_csv.insert(with_csv.end(), {"--csv", csv});
    const CliResult r = run_clothsim(with_csv);
    EXPECT_EQ(r.exit_code, 2) << message << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << message;
  }
  EXPECT_TRUE(only_files(dir, {}));
}

}  // namespace
}  // namespace clothsim::testing
