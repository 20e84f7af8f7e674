// `clothsim stability` as users call it: the undamped spring's limits in the CSV, and bad
// parameters and lists answered in one line with exit 2 and nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

std::string spring() { return std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml"; }

std::vector<std::vector<std::string>> csv_rows(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

TEST(CmdStability, FindsTheUndampedSpringsLimitsAndPrintsTheEstimate) {
  const std::string dir = scratch_dir("stability_csv");
  const CliResult r = run_clothsim({"stability", spring(), "--set", "cloth.springs.structural.damping=0",
                                    "--integrators", "symplectic_euler,implicit_euler,explicit_euler", "--values",
                                    "100,400", "--duration", "400", "--min-dt", "0.02", "--max-dt", "1", "--csv",
                                    dir + "/st.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2/w_max"), std::string::npos);
  const auto rows = csv_rows(dir + "/st.csv");
  ASSERT_EQ(rows.size(), 1u + 6u);
  EXPECT_EQ(rows[0][0], "param");
  EXPECT_EQ(rows[0][4], "stable_dt");
  // k = 100: w = 10, symplectic Euler's limit 2 / w = 0.2 s; implicit Euler at the cap;
  // explicit Euler unstable down to w h = 0.2.
  EXPECT_EQ(rows[1][2], "symplectic_euler");
  EXPECT_EQ(rows[1][3], "bracketed");
  EXPECT_NEAR(std::atof(rows[1][4].c_str()), 0.2, 0.03 * 0.2);
  EXPECT_NEAR(std::atof(rows[1][10].c_str()), 0.2, 1e-12);  // dt_springs: 2 / w_max
  EXPECT_EQ(rows[2][3], "stable_at_max");
  EXPECT_EQ(rows[3][3], "unstable_at_min");
  // k = 400: w = 20, limit 0.1 s.
  EXPECT_NEAR(std::atof(rows[4][4].c_str()), 0.1, 0.03 * 0.1);
  EXPECT_TRUE(only_files(dir, {"st.csv"}));
}

TEST(CmdStability, TheAliasKsSweepsEverySpringTypeAndLabelsTheSweepKs) {
  // The spring scene has one structural spring: ks is that key, and the limits are the same
  // as the dotted path's; the CSV's param column (the plot's axis) says ks.
  const std::string dir = scratch_dir("stability_alias");
  const std::vector<std::string> base{"stability", spring(), "--set", "cloth.springs.structural.damping=0",
                                      "--integrators", "symplectic_euler", "--values", "100", "--duration", "400",
                                      "--min-dt", "0.02", "--max-dt", "1"};
  std::vector<std::string> alias = base, path = base;
  alias.insert(alias.end(), {"--param", "ks", "--csv", dir + "/ks.csv"});
  path.insert(path.end(), {"--param", "cloth.springs.structural.stiffness", "--csv", dir + "/path.csv"});
  ASSERT_EQ(run_clothsim(alias).exit_code, 0);
  ASSERT_EQ(run_clothsim(path).exit_code, 0);
  const auto by_alias = csv_rows(dir + "/ks.csv"), by_path = csv_rows(dir + "/path.csv");
  ASSERT_EQ(by_alias.size(), 2u);
  ASSERT_EQ(by_path.size(), 2u);
  EXPECT_EQ(by_alias[1][0], "ks");
  EXPECT_EQ(by_alias[1][4], by_path[1][4]) << "the same sweep, named two ways";
  const CliResult glob = run_clothsim({"stability", spring(), "--param", "spheres.*.radius", "--values", "1"});
  EXPECT_EQ(glob.exit_code, 2) << glob.err;
  EXPECT_NE(glob.err.find("--param"), std::string::npos) << glob.err;
}

TEST(CmdStability, AnUnknownParamIsSaidOfParamAsTyped) {
  const CliResult r = run_clothsim({"stability", spring(), "--param", "kss", "--values", "1,2"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(": --param kss: unknown key"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("--set"), std::string::npos) << r.err;
}

TEST(CmdStability, AMisspeltParamIsAnUnknownKeyWithTheNearest) {
  // Without --values it said the key "gives no number to scale the default values from".
  const CliResult r = run_clothsim({"stability", spring(), "--param", "cloth.springs.structural.stifness"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(": --param cloth.springs.structural.stifness: unknown key (did you mean stiffness? "),
            std::string::npos)
      << r.err;
}

TEST(CmdStability, WithoutDurationRunsToTheDefaultItsHelpStates) {
  EXPECT_NE(run_clothsim({"stability", "--help"}).out.find("--duration FLOAT            Simulated time in s "
                                                          "(default: the scene's duration, at most 0.2 s)"),
            std::string::npos);
  // spring.yaml lasts 2 s: capped at 0.2 s; a scene shorter than that keeps its own.
  const CliResult capped = run_clothsim({"stability", spring(), "--integrators", "symplectic_euler", "--values", "100"});
  ASSERT_EQ(capped.exit_code, 0) << capped.err;
  EXPECT_NE(capped.out.find("each run 0 to T = 0.2 s"), std::string::npos) << capped.out;
  const CliResult shorter = run_clothsim({"stability", spring(), "--set", "duration=0.15", "--integrators",
                                          "symplectic_euler", "--values", "100"});
  ASSERT_EQ(shorter.exit_code, 0) << shorter.err;
  EXPECT_NE(shorter.out.find("each run 0 to T = 0.15 s"), std::string::npos) << shorter.out;
}

TEST(CmdStability, BadParametersAndListsAreOneLineExitTwoAndNothingWritten) {
  const std::string dir = scratch_dir("stability_bad");
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases{
      {{"--param", "cloth.springs.structural.stifness", "--values", "1,2"}, "stifness"},
      {{"--param", "cloth.plane", "--values", "1,2"}, "cloth.plane is not a numeric scene key"},
      {{"--param", "name", "--values", "1,2"}, "name is not a numeric scene key"},
      {{"--param", "air_drag"}, "--values: "},  // absent from the file: no value to scale from
      {{"--values", ""}, "--values: empty list"},
      {{"--values", "100,x"}, "--values: 'x' is not a finite number"},
      {{"--max-dt", "1", "--duration", "2"}, "leaves fewer than 20 steps"},
      {{"--integrators", ""}, "--integrators: empty list"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"stability", spring(), "--csv", dir + "/st.csv"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliResult r = run_clothsim(args);
    EXPECT_EQ(r.exit_code, 2) << c.message << "\n" << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_TRUE(only_files(dir, {})) << c.message;
  }
}

// A run that reached T with implicit steps above their tolerance is not stable: the search
// goes below it, and the table, the CSV and the plot say it failed by its solve.
TEST(CmdStability, AnUnconvergedImplicitRunIsNotStableAndTheCsvSaysSo) {
  const std::string dir = scratch_dir("stability_unconverged");
  // Two Newton iterations meet 1e-10 on the swinging spring up to 0.02 s, not at 0.05 s.
  const CliResult r = run_clothsim({"stability", spring(), "--set", "gravity=[0,-9.8,0]", "--set",
                                    "implicit.newton_max_iterations=2", "--set", "implicit.newton_tolerance=1e-10",
                                    "--integrators", "implicit_euler", "--values", "100", "--duration", "2",
                                    "--min-dt", "0.001", "--max-dt", "0.1", "--frame-dts", "1/100,1/10",
                                    "--csv", dir + "/st.csv", "--plot", dir + "/st.png"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(NOT CONVERGED at "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("one step per frame: 1/100 s: ok, 200 steps converged; 1/10 s: 20 of 20 steps not converged"),
            std::string::npos) << r.out;
  const auto rows = csv_rows(dir + "/st.csv");
  ASSERT_EQ(rows.size(), 2u);
  const auto column = [&rows](const std::string& name) {
    const auto at = std::find(rows[0].begin(), rows[0].end(), name);
    EXPECT_NE(at, rows[0].end()) << name;
    return static_cast<std::size_t>(at - rows[0].begin());
  };
  EXPECT_EQ(rows[1][column("outcome")], "bracketed");
  EXPECT_EQ(rows[1][column("failure")], "not_converged");
  EXPECT_NE(rows[1][column("reason")].find("steps not converged"), std::string::npos);
  EXPECT_LE(std::atof(rows[1][column("unstable_dt")].c_str()), 0.05 * 1.0001);
  EXPECT_EQ(slurp(dir + "/st.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

// python3-matplotlib is one of the project's dependencies: the plot must be drawn.
TEST(CmdStability, InterruptKeepsTheSearchesFinishedSoFarAndNamesEveryFileThatStays) {
  // The drape's 20 searches over 2 s of scene take about 22 s on an idle machine, far longer
  // than the 5 s before SIGINT; 5 s, not less, so that a loaded machine has finished planning
  // (a signal before the study starts writes nothing, another test's case).
  const std::string dir = scratch_dir("stability_interrupt");
  const CliResult r = run_clothsim({"stability", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--duration", "2",
                                    "--csv", dir + "/st.csv", "--summary", dir + "/st.json", "--plot", dir + "/st.png"},
                                   "timeout --foreground --preserve-status -s INT 5");
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("clothsim: stopped by SIGINT: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" of 20 searches finished; kept " + dir + "/st.csv (incomplete), " + dir +
                       "/st.json (incomplete); not written: " + dir + "/st.png"),
            std::string::npos)
      << r.err;
  const auto rows = csv_rows(dir + "/st.csv");
  ASSERT_GE(rows.size(), 1u);
  EXPECT_EQ(rows[0].at(0), "param");
  EXPECT_NE(slurp(dir + "/st.json").find("\"complete\": false"), std::string::npos);
  EXPECT_TRUE(only_files(dir, {"st.csv", "st.json"}));
}

TEST(CmdStability, DrawsTheStabilityMap) {
  const std::string dir = scratch_dir("stability_plot");
  const CliResult r = run_clothsim({"stability", spring(), "--integrators", "symplectic_euler,rk4,implicit_euler",
                                    "--values", "100,1000", "--duration", "20", "--plot", dir + "/st.png"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(dir + "/st.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_TRUE(only_files(dir, {"st.png"}));
}

TEST(CmdStability, RefusesASmallestStepPastTheStepLimitAtOnce) {
  const CliResult r = run_clothsim({"stability", spring(), "--min-dt", "1e-12", "--duration", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("at the smallest step tried, duration / dt = 1 s / 1e-12 s"), std::string::npos) << r.err;
}

// Below ~1e-15 the bracket's ends are neighbouring doubles: 1e-16 once bisected forever.
TEST(CmdStability, APrecisionFinerThanDoublesCanResolveIsRefused) {
  const CliResult r = run_clothsim({"stability", spring(), "--precision", "1e-16", "--integrators",
                                    "symplectic_euler", "--values", "1e6"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("the precision must be from 1e-12 to 1"), std::string::npos) << r.err;
}

// stability takes compare's lanes, each searched on its own settings: the course's one-iteration
// fixed point is stable only for w h <= 1 on the undamped spring (w = 10: 0.1 s), implicit
// Euler's converged Newton solve at every step tried; xpbd:3 is searched and labelled so.
TEST(CmdStability, SearchesEachLaneOnItsOwnSettingsAndLabelsItAsCompareDoes) {
  const std::string dir = scratch_dir("stability_lanes");
  const CliResult r = run_clothsim({"stability", spring(), "--set", "cloth.springs.structural.damping=0",
                                    "--integrators", "implicit_euler,implicit_euler_fixed_point,xpbd:3", "--values",
                                    "100", "--duration", "20", "--min-dt", "0.01", "--max-dt", "0.5",
                                    "--frame-dts", "1/30", "--csv", dir + "/st.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("implicit_euler (fixed point)"), std::string::npos) << r.out;
  const auto rows = csv_rows(dir + "/st.csv");
  ASSERT_EQ(rows.size(), 1u + 3u);
  EXPECT_EQ(rows[1][2], "implicit_euler");
  EXPECT_EQ(rows[2][2], "implicit_euler_fixed_point");
  EXPECT_EQ(rows[3][2], "xpbd:3");
  EXPECT_EQ(rows[1][3], "stable_at_max");
  EXPECT_EQ(rows[2][3], "bracketed");
  const double fixed_point = std::atof(rows[2][4].c_str());
  EXPECT_NEAR(fixed_point, 0.1, 0.03 * 0.1);  // w h = 1
  EXPECT_LT(fixed_point, std::atof(rows[1][4].c_str()));
}

TEST(CmdStability, ALaneStepIsOneLineExitTwoSayingTheStepIsSearched) {
  const std::string dir = scratch_dir("stability_lane_step");
  const CliResult r = run_clothsim({"stability", spring(), "--integrators", "xpbd@1e-3:3", "--csv", dir + "/st.csv"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("stability searches the step, so a lane takes no @STEP (its :N stays fixed while the step "
                       "is searched)"), std::string::npos) << r.err;
  EXPECT_TRUE(only_files(dir, {}));
}

}  // namespace
}  // namespace clothsim::testing
