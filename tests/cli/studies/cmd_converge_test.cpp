// `clothsim converge` as users call it: the CSV's rows and columns, the table, and bad
// options answered in one line with exit 2 and nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

std::string stiff() { return std::string(CLOTHSIM_SCENES_DIR) + "/stiff.yaml"; }

TEST(CmdConverge, WritesOneRowPerMethodStateAndIterationCount) {
  const std::string dir = scratch_dir("converge");
  const CliResult r = run_clothsim({"converge", stiff(), "--dt", "1/30", "--states", "2", "--max-iterations", "3",
                                    "--integrators", "vbd,implicit_euler", "--csv", dir + "/c.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("to 1 mm"), std::string::npos) << r.out;
  std::ifstream in(dir + "/c.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "scene,method,state,t,iterations,rms_distance,max_distance,gradient_norm,cpu_seconds,wrong");
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_EQ(rows, 2 * 2 * 3);
}

std::vector<std::string> small_study(const std::string& csv) {
  return {"converge", stiff(), "--dt", "1/30", "--states", "2", "--max-iterations", "3",
          "--integrators", "xpbd,implicit_euler", "--csv", csv};
}

// The CSV without its ninth column, cpu_seconds, which measures the machine (the columns before
// it hold no comma; `wrong`, after it, may).
std::string untimed(const std::string& path) {
  std::string out;
  std::istringstream in(slurp(path));
  for (std::string line; std::getline(in, line);) {
    std::size_t start = 0;
    for (int i = 0; i < 8 && start != std::string::npos; ++i) start = line.find(',', start) + 1;
    const std::size_t end = line.find(',', start);
    out += line.substr(0, start) + (end == std::string::npos ? "" : line.substr(end + 1)) + "\n";
  }
  return out;
}

TEST(CmdConverge, ShardsMergeIntoWhatOneProcessWritesAndARerunRunsNothingTwice) {
  const std::string dir = scratch_dir("converge_shards");
  for (const char* k : {"1/2", "2/2"}) {
    std::vector<std::string> args = small_study(dir + "/p.csv");
    args.insert(args.end(), {"--shard", k});
    const CliResult r = run_clothsim(args);
    ASSERT_EQ(r.exit_code, 0) << k << r.err;
    EXPECT_NE(r.out.find("of converge: 2 of 4 items"), std::string::npos) << r.out;  // balanced by cost
  }
  std::vector<std::string> whole = small_study(dir + "/one.csv");
  whole.insert(whole.end(), {"--plot", dir + "/one.png"});
  const CliResult one = run_clothsim(whole);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const CliResult m = run_clothsim({"merge", dir + "/p.csv.shard-1-of-2", dir + "/p.csv.shard-2-of-2", "--csv",
                                    dir + "/m.csv", "--plot", dir + "/m.png"});
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_GT(std::filesystem::file_size(dir + "/one.png"), 0u);
  EXPECT_GT(std::filesystem::file_size(dir + "/m.png"), 0u);
  EXPECT_EQ(line_count(slurp(dir + "/m.csv")), 1 + 2 * 2 * 3);
  EXPECT_EQ(untimed(dir + "/m.csv"), untimed(dir + "/one.csv"));
  const CliResult no_summary = run_clothsim({"merge", dir + "/p.csv.shard-1-of-2", dir + "/p.csv.shard-2-of-2",
                                             "--csv", dir + "/s.csv", "--summary", dir + "/s.json"});
  EXPECT_EQ(no_summary.exit_code, 2);  // a merged converge's JSON would only repeat the CSV's means
  EXPECT_EQ(std::count(no_summary.err.begin(), no_summary.err.end(), '\n'), 1) << no_summary.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/s.csv") || std::filesystem::exists(dir + "/s.json"));

  std::vector<std::string> again = small_study(dir + "/p.csv");
  again.insert(again.end(), {"--shard", "1/2"});
  const CliResult r = run_clothsim(again);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 finished before, 0 to run"), std::string::npos) << r.out;
  EXPECT_EQ(line_count(slurp(dir + "/p.csv.shard-1-of-2/log")), 2);  // one record per item, none twice
}

TEST(CmdConverge, BadOptionsAreOneLineExitTwoAndNothingWritten) {
  const std::string dir = scratch_dir("converge_bad");
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--states", "0"}, {"--max-iterations", "-4"}, {"--max-iterations", "1e9"},
        {"--integrators", "rk4"}, {"--dt", "fast"}}) {
    std::vector<std::string> args{"converge", stiff(), "--csv", dir + "/c.csv"};
    args.insert(args.end(), bad.begin(), bad.end());
    const CliResult r = run_clothsim(args);
    EXPECT_EQ(r.exit_code, 2) << bad[0] << " " << bad[1];
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/c.csv"));
  }
}

TEST(CmdRunIterations, BadCountsAndIntegratorsWithoutIterationsAreRefused) {
  for (const char* bad : {"0", "-1", "ten", "1000001"}) {
    const CliResult r = run_clothsim({"run", stiff(), "--integrator", "vbd", "--iterations", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--iterations"), std::string::npos) << r.err;
  }
  const CliResult rk4 = run_clothsim({"run", stiff(), "--integrator", "rk4", "--iterations", "3"});
  EXPECT_EQ(rk4.exit_code, 2);
  EXPECT_NE(rk4.err.find("rk4 has no iterations"), std::string::npos) << rk4.err;
  const CliResult ok = run_clothsim({"run", stiff(), "--integrator", "xpbd", "--iterations", "2", "--duration", "0.1"});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("xpbd: 100 iterations"), std::string::npos) << ok.out;  // 50 steps of 2
}

}  // namespace
}  // namespace clothsim::testing
