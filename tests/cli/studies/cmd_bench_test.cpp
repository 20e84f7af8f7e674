// `clothsim bench` as users call it: the CSV and the printed reference check, a reference
// that is not converged failing loudly, bad step lists answered in one line with exit 2
// and nothing written, Ctrl-C keeping the runs finished so far, and the plot.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <fstream>
#include <iterator>
#include <sstream>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

std::string spring() { return std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml"; }

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(CmdBench, WritesOneRowPerRunAndPrintsTheReferenceCheck) {
  const std::string dir = scratch_dir("bench_csv");
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "symplectic_euler,rk4", "--dts",
                                    "0.01,0.005", "--duration", "1", "--csv", dir + "/wp.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  // The spring is a smooth scene: its reference is the adaptive pair, and its own error is printed.
  EXPECT_NE(r.out.find("reference check: tightening the adaptive reference's tolerance (dopri5, 1e-11 -> 1e-13) "
                       "moved the particles by"),
            std::string::npos)
      << r.out;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_EQ(rows.size(), 1u + 4u);
  EXPECT_EQ(rows[0].rfind("integrator,dt,steps,force_evals,", 0), 0u);
  EXPECT_EQ(rows[1].rfind("symplectic_euler,0.005,200,200,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[4].rfind("rk4,0.01,100,400,", 0), 0u) << rows[4];
  EXPECT_TRUE(only_files(dir, {"wp.csv"}));
}

TEST(CmdBench, ASecondRunReusesTheReferenceAndWritesTheSameCsvButItsTimings) {
  const std::string dir = scratch_dir("bench_reference_cache");
  const std::string env = "env -u CLOTHSIM_REFERENCE_CACHE_MAX XDG_CACHE_HOME=" + shell_quote(dir + "/xdg");
  const auto bench = [&](const std::string& csv, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"bench", spring(), "--integrators", "midpoint,rk4", "--dts", "0.01,0.005",
                                     "--duration", "1", "--csv", dir + "/" + csv};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_clothsim(args, env);
  };
  const CliResult cold = bench("cold.csv"), warm = bench("warm.csv");
  ASSERT_EQ(cold.exit_code, 0) << cold.err;
  ASSERT_EQ(warm.exit_code, 0) << warm.err;
  EXPECT_NE(cold.out.find("reference: computed, and stored in the cache (" + dir + "/xdg/clothsim/"), std::string::npos)
      << cold.out;
  EXPECT_NE(warm.out.find("reference: reused from the cache (" + dir + "/xdg/clothsim/"), std::string::npos) << warm.out;
  // Every column but wall_seconds and cpu_seconds (the 7th and 8th), row for row.
  const auto untimed = [](const std::string& row) {
    std::vector<std::string> cells;
    std::stringstream in(row);
    for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
    if (cells.size() > 8) cells.erase(cells.begin() + 6, cells.begin() + 8);
    return cells;
  };
  const auto a = lines(dir + "/cold.csv"), b = lines(dir + "/warm.csv");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(untimed(a[k]), untimed(b[k])) << k;
  const CliResult off = bench("off.csv", {"--no-reference-cache"});
  EXPECT_NE(off.out.find("reference: computed (the cache is off: --no-reference-cache"), std::string::npos) << off.out;
}

TEST(CmdBench, WithoutDurationRunsToTheDefaultItsHelpStates) {
  EXPECT_NE(run_clothsim({"bench", "--help"}).out.find("(default: the scene's duration, at most 0.5 s and 8000 x the "
                                                      "smallest step, rounded down to a multiple of the largest)"),
            std::string::npos);
  // spring.yaml: 2 s, dt 1 ms, so steps 0.25 .. 8 ms: min(2, 0.5, 8000 x 0.25 ms) = 0.5 s, down
  // to a multiple of 8 ms = 0.496 s.
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "symplectic_euler"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("to T = 0.496 s"), std::string::npos) << r.out;
}

TEST(CmdBench, TakesStepsAsFractions) {
  const std::string dir = scratch_dir("bench_fractions");
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "symplectic_euler", "--dts", "1/100,1/200",
                                    "--duration", "1", "--csv", dir + "/wp.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_EQ(rows.size(), 1u + 2u);
  EXPECT_EQ(rows[1].rfind("symplectic_euler,0.005,200,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("symplectic_euler,0.01,100,", 0), 0u) << rows[2];
}

TEST(CmdBench, FailsLoudlyWhenTheReferenceIsNotConverged) {
  // A ground far below makes the spring a scene with projected contacts, whose reference is
  // fixed-step RK4. --reference-refinement 1: it runs at the bench's own step, so RK4's error
  // there is its own, far under 10x what halving the reference moves it: unresolved.
  const std::string dir = scratch_dir("bench_unconverged");
  const CliResult r = run_clothsim({"bench", spring(), "--set", "ground={height: -5}", "--integrators", "rk4",
                                    "--dts", "0.01", "--duration", "1", "--reference-refinement", "1", "--csv",
                                    dir + "/wp.csv", "--summary", dir + "/wp.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("the reference is not converged"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("spring.yaml"), std::string::npos) << r.err;
  // Both kept for inspection, and said so.
  EXPECT_NE(r.err.find("(kept for inspection: " + dir + "/wp.csv, " + dir + "/wp.json); no plot drawn"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(lines(dir + "/wp.csv").size(), 2u);
  EXPECT_TRUE(only_files(dir, {"wp.csv", "wp.json"}));
}

TEST(CmdBench, ARunUnderTenTimesTheReferencesErrorIsUnresolvedAndTheSummaryStatesThatError) {
  // A loose reference (1e-8, checked at 1e-6): RK4's 1e-11 m at 1 ms is far under its
  // estimate, so no number is given for it, and a reference above round-off that cannot resolve
  // a run fails the study; symplectic Euler's 1e-4 m is resolved.
  const std::string dir = scratch_dir("bench_unresolved");
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "symplectic_euler,rk4", "--dts", "0.001",
                                    "--duration", "0.5", "--reference-tolerance", "1e-6", "--csv", dir + "/wp.csv",
                                    "--summary", dir + "/wp.json"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("the reference is not converged: tightening its tolerance (1e-06 -> 1e-08)"),
            std::string::npos)
      << r.err;
  const std::size_t row = r.out.find("\nrk4 ");
  ASSERT_NE(row, std::string::npos) << r.out;
  const std::string text = r.out.substr(row + 1, r.out.find('\n', row + 1) - row - 1);
  EXPECT_NE(text.find("-            -  unresolved: under 10 x the reference's error"), std::string::npos) << text;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_EQ(rows.size(), 3u);
  const auto column = [&](const std::string& row, const std::string& name) {  // by the header's name
    std::vector<std::string> names, cells;
    std::stringstream h(rows[0]), c(row);
    for (std::string s; std::getline(h, s, ',');) names.push_back(s);
    for (std::string s; std::getline(c, s, ',');) cells.push_back(s);
    const auto at = std::find(names.begin(), names.end(), name) - names.begin();
    return static_cast<std::size_t>(at) < cells.size() ? cells[at] : std::string("(none)");
  };
  EXPECT_EQ(column(rows[1], "unresolved"), "0") << rows[1];
  EXPECT_EQ(column(rows[2], "unresolved"), "1") << rows[2];
  EXPECT_EQ(column(rows[2], "error_measure"), "time") << rows[2];
  std::ifstream json_in(dir + "/wp.json");
  const std::string json((std::istreambuf_iterator<char>(json_in)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"integrator\": \"dopri5 (adaptive)\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"estimated_error_m\": "), std::string::npos) << json;
  EXPECT_NE(json.find("\"unresolved\": true"), std::string::npos) << json;
}

TEST(CmdBench, BadStepListsAreOneLineExitTwoAndNothingWritten) {
  const std::string dir = scratch_dir("bench_bad");
  const std::string csv = dir + "/wp.csv";
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases{
      {{"--dts", ""}, "--dts"},  // CLI11's own "required LIST missing"
      {{"--dts", ","}, "--dts: empty item"},
      {{"--dts=0.01,-0.005"}, "--dts: -0.005 is not a positive step"},
      {{"--dts", "0.01,abc"}, "--dts: 'abc' is not a finite number"},
      {{"--dts", "1/0"}, "--dts: '1/0' is not a finite number (or a fraction like 1/60)"},
      {{"--frame-dts", "1/60,0"}, "--frame-dts: 0 is not a positive step"},
      {{"--frame-dts", "sixty"}, "--frame-dts: 'sixty' is not a finite number"},
      {{"--dts", "0.003", "--duration", "1"}, "--dts: 0.003 does not divide the duration 1 s"},
      {{"--integrators", "rk5"}, "--integrators: unknown integrator 'rk5'"},
      {{"--integrators", "rk4,rk4"}, "--integrators: 'rk4' is listed twice"},
      {{"--tols", "1e-6"}, "--tols: no adaptive lane to sweep"},
      {{"--integrators", "dopri5:tol=1e-6"}, "bench sweeps an adaptive lane's tolerance (--tols)"},
      {{"--integrators", "dopri5", "--tols", "1e-6,2"}, "--tols: 2 is not a tolerance in (0, 1)"},
      {{"--integrators", "dopri5", "--tols", "1e-6,1e-6"}, "--tols: 1e-06 is listed twice"},
      {{"--error", "sometimes"}, "--error: expected time"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"bench", spring(), "--csv", csv};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliResult r = run_clothsim(args);
    EXPECT_EQ(r.exit_code, 2) << c.message;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_TRUE(only_files(dir, {})) << c.message;
  }
}

TEST(CmdBench, InterruptKeepsTheRunsFinishedSoFarAndNamesEveryFileThatStays) {
  // The drape's reference runs over 2 s of scene take far longer than the 5 s before SIGINT (its
  // first run ends after about 40 s on an idle machine; the study at 0.2 s had become fast enough
  // to finish first; 5 s, not 2, so that a loaded machine has finished planning, since a signal
  // before the study starts writes nothing); SIGINT stops the study, which writes
  // the CSV and the summary of what finished (a header at least) and exits 130 (128 + SIGINT),
  // its one line naming both files as incomplete and the plot as not drawn.
  const std::string dir = scratch_dir("bench_interrupt");
  const CliResult r = run_clothsim({"bench", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--duration", "2",
                                    "--csv", dir + "/wp.csv", "--summary", dir + "/wp.json", "--plot", dir + "/wp.png"},
                                   "timeout --foreground --preserve-status -s INT 5");
  EXPECT_EQ(r.exit_code, 130) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("clothsim: stopped by SIGINT: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" of 28 runs finished; kept " + dir + "/wp.csv (incomplete), " + dir +
                       "/wp.json (incomplete); not written: " + dir + "/wp.png"),
            std::string::npos)
      << r.err;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_GE(rows.size(), 1u);
  EXPECT_EQ(rows[0].rfind("integrator,dt,", 0), 0u);
  EXPECT_NE(slurp(dir + "/wp.json").find("\"complete\": false"), std::string::npos);
  EXPECT_TRUE(only_files(dir, {"wp.csv", "wp.json"}));
}

// python3-matplotlib is one of the project's dependencies (tools/install-deps.sh): the plot
// must be drawn, not skipped.
TEST(CmdBench, DrawsTheWorkPrecisionDiagram) {
  const std::string dir = scratch_dir("bench_plot");
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "explicit_euler,rk4", "--dts", "0.01,0.005",
                                    "--duration", "1", "--plot", dir + "/wp.png"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(dir + "/wp.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_TRUE(only_files(dir, {"wp.png"}));  // the temporary CSV and PNG are gone
}

TEST(CmdBench, APythonWithoutMatplotlibIsSaidBeforeAnyRun) {
  const std::string dir = scratch_dir("bench_plot_missing");
  // /bin/false stands in for a python3 that cannot import matplotlib.
  const CliResult r = run_clothsim({"bench", spring(), "--dts", "0.01,0.005", "--duration", "1", "--plot",
                                    dir + "/wp.png"},
                                   "env CLOTHSIM_PYTHON=/bin/false");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("matplotlib"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");  // no study ran
  EXPECT_TRUE(only_files(dir, {}));
}

// Steps are bounded before anything runs: the finest reference run of --dts 1e-9 over 1 s
// (the smallest step / 8 / 2) is 1.6e10 steps.
TEST(CmdBench, RefusesAStudyPastTheStepLimitAtOnce) {
  const CliResult r = run_clothsim({"bench", spring(), "--dts", "1e-9", "--duration", "1"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--dts: the finest reference run: duration / dt"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("more than the limit of 1e+09"), std::string::npos) << r.err;
}

// A scene whose implicit_euler is the fixed point (--set implicit.solver=fixed_point) was
// labelled implicit_euler, so its rows could not be told from backward Euler's.
TEST(CmdBench, ASceneSetToTheFixedPointNamesItsLanesSo) {
  const std::string dir = scratch_dir("bench_scene_fixed_point");
  const CliResult r = run_clothsim({"bench", spring(), "--set", "implicit.solver=fixed_point", "--integrators",
                                    "implicit_euler", "--dts", "0.01,0.005", "--duration", "1", "--frame-dts", "none",
                                    "--csv", dir + "/wp.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("implicit_euler (fixed point)"), std::string::npos) << r.out;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_NE(rows[1].find("implicit_euler_fixed_point"), std::string::npos) << rows[1];
}

// bench takes compare's lanes: `course` is four rows labelled as compare labels its lanes,
// the CSV's integrator column holds each lane's spelling, and a lane's own settings apply.
TEST(CmdBench, TakesTheCourseAndIterationLanesAndLabelsThemAsCompareDoes) {
  const std::string dir = scratch_dir("bench_lanes");
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "course,xpbd:3", "--dts", "0.01,0.005",
                                    "--duration", "1", "--frame-dts", "1/10", "--csv", dir + "/wp.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("implicit_euler (fixed point)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  xpbd:3 "), std::string::npos) << r.out;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_EQ(rows.size(), 1u + 5u * 2u + 1u);  // five lanes at two steps, the fixed point at 1/10 s too
  std::vector<std::string> names;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const std::string name = rows[i].substr(0, rows[i].find(','));
    if (names.empty() || names.back() != name) names.push_back(name);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"explicit_euler", "implicit_euler_fixed_point", "midpoint", "rk4",
                                             "xpbd:3"}));
  EXPECT_TRUE(only_files(dir, {"wp.csv"}));
}

TEST(CmdBench, ALaneStepIsOneLineExitTwoSayingBenchSweepsTheStep) {
  const std::string dir = scratch_dir("bench_lane_step");
  for (const char* lanes : {"rk4@1e-3", "course,xpbd@1/600:3"}) {
    const CliResult r = run_clothsim({"bench", spring(), "--integrators", lanes, "--csv", dir + "/wp.csv"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("bench sweeps the step (--dts), so a lane takes no @STEP"), std::string::npos) << r.err;
    EXPECT_TRUE(only_files(dir, {}));
  }
}

TEST(CmdBench, VaryRunsTheStudyPerValueWithLanesLabelledByTheValue) {
  // The spring at two stiffnesses: each value against its own reference, its rows labelled
  // "symplectic_euler (ks = 400)" in the table and the CSV; the stiffer spring, the larger error.
  const std::string dir = scratch_dir("bench_vary");
  const CliResult r = run_clothsim({"bench", spring(), "--vary", "ks=100,400", "--integrators", "symplectic_euler",
                                    "--dts", "0.01,0.005", "--duration", "1", "--csv", dir + "/wp.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\nsymplectic_euler (ks = 100)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nsymplectic_euler (ks = 400)"), std::string::npos) << r.out;
  const auto rows = lines(dir + "/wp.csv");
  ASSERT_EQ(rows.size(), 1u + 4u);
  EXPECT_EQ(rows[0].rfind("integrator,dt,steps,force_evals,", 0), 0u);
  ASSERT_EQ(rows[2].rfind("symplectic_euler (ks = 100),0.01,100,100,", 0), 0u) << rows[2];
  ASSERT_EQ(rows[4].rfind("symplectic_euler (ks = 400),0.01,100,100,", 0), 0u) << rows[4];
  const auto error = [](const std::string& row) {  // the 9th column, rms_error
    std::size_t at = 0;
    for (int comma = 0; comma < 8; ++comma) at = row.find(',', at) + 1;
    return std::stod(row.substr(at));
  };
  EXPECT_GT(error(rows[4]), 2.0 * error(rows[2])) << "a stiffer spring, a faster oscillation, a larger error";
  // A summary or a shard holds one scene's study: refused in one line with --vary.
  const CliResult refused = run_clothsim({"bench", spring(), "--vary", "ks=100,400", "--summary", dir + "/s.json"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_EQ(line_count(refused.err), 1) << refused.err;
  EXPECT_NE(refused.err.find("--vary: --summary and --shard"), std::string::npos) << refused.err;
  EXPECT_EQ(run_clothsim({"bench", spring(), "--vary", "ks"}).exit_code, 2);
}

}  // namespace
}  // namespace clothsim::testing
