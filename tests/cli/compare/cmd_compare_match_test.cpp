// clothsim compare --match and the WRONG verdict, through the built binary: which step each
// lane runs at and how the table says it was chosen; a finite but implausible lane flagged in
// the table, the summary and on its tile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_process.h"
#include "cli/compare/compare_small.h"

namespace fs = std::filesystem;
namespace cli = clothsim::testing;
using clothsim::testing::run_clothsim;
using clothsim::testing::scratch_dir;

namespace {

using clothsim::testing::compare_small;
using clothsim::testing::kDrape;

// The table's row for `lane` (its first line starting with the name and a space).
std::string row_of(const std::string& out, const std::string& lane) {
  const std::size_t at = out.find("\n" + lane + " ");
  return at == std::string::npos ? std::string() : out.substr(at + 1, out.find('\n', at + 1) - at - 1);
}

double step_of(const std::string& out, const std::string& lane) {
  double dt = -1.0;
  std::sscanf(row_of(out, lane).c_str() + lane.size(), "%lf", &dt);
  return dt;
}

}  // namespace

TEST(CmdCompareMatch, ByDefaultLanesRunAtTheStepOfEqualCostAndTheTableSaysSo) {
  const std::string dir = scratch_dir("compare_match_cost");
  const auto r = compare_small({"--integrators", "explicit_euler,midpoint,rk4@1e-4", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_DOUBLE_EQ(step_of(r.out, "explicit_euler"), 1e-4) << r.out;
  EXPECT_DOUBLE_EQ(step_of(r.out, "midpoint"), 2e-4) << "two evaluations a step: twice the step\n" << r.out;
  EXPECT_DOUBLE_EQ(step_of(r.out, "rk4"), 1e-4) << "a lane with its own @STEP keeps it\n" << r.out;
  EXPECT_NE(r.out.find("step of midpoint: 0.0002 s, matched on cost"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("step of rk4: 1e-4 s, your step"), std::string::npos) << r.out;
  const std::string json = cli::slurp(dir + "/s.json");
  EXPECT_NE(json.find("\"match\": \"cost\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"step_choice\": \"matched on cost"), std::string::npos) << json;
}

// An iterative solver's step costs its iterations (work_units.h weighs each solver's), so a
// solver lane matched on cost runs at the step where N iterations a step cost what explicit
// Euler's one evaluation a step does at 1e-4 s: xpbd:10 at 10 x 1.4 passes, vbd:10 at
// 10 x 2.4 passes plus its first guess's evaluation.
TEST(CmdCompareMatch, SolverLanesAreMatchedOnTheirIterations) {
  const std::string dir = scratch_dir("compare_match_solvers");
  const auto r = compare_small(
      {"--integrators", "explicit_euler,xpbd:10,vbd:10,projective_dynamics:5", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(step_of(r.out, "xpbd:10"), 14 * 1e-4, 1e-6) << r.out;
  EXPECT_NEAR(step_of(r.out, "vbd:10"), 25 * 1e-4, 1e-6) << r.out;
  const double pd = step_of(r.out, "projective_dynamics:5");
  EXPECT_GT(pd, 5 * 1e-4) << "five iterations of several passes each\n" << r.out;
  EXPECT_TRUE(std::isfinite(pd)) << r.out;
}

TEST(CmdCompareMatch, NoneKeepsTheScenesStep) {
  const std::string dir = scratch_dir("compare_match_none");
  const auto r = compare_small({"--integrators", "explicit_euler,midpoint", "--match", "none", "--summary",
                                dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_DOUBLE_EQ(step_of(r.out, "midpoint"), 1e-4) << r.out;
  EXPECT_NE(r.out.find("step of midpoint: 0.0001 s, the scene's step (--match none)"), std::string::npos) << r.out;
}

TEST(CmdCompareMatch, ErrorGivesTheLargestStepWithinTheToleranceSaidInTheTable) {
  const std::string dir = scratch_dir("compare_match_error");
  const auto r = compare_small({"--integrators", "symplectic_euler,rk4", "--match", "error", "1e-3", "--video",
                                dir + "/v.mp4", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("step of rk4: 1/"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("matched on error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("bisection"), std::string::npos) << r.out;
  EXPECT_GT(step_of(r.out, "rk4"), step_of(r.out, "symplectic_euler"))
      << "the fourth-order method reaches the same error at a longer step\n" << r.out;
  // The clip is coloured against the reference the steps were matched against, at frames both
  // land on: its own numbers stay within the tolerance too.
  for (const std::string lane : {"symplectic_euler", "rk4"}) {
    const std::size_t at = r.out.find(lane + " @ ");
    ASSERT_NE(at, std::string::npos) << r.out;
    double largest = -1.0;
    ASSERT_NE(r.out.find("largest ", at), std::string::npos) << r.out;
    std::sscanf(r.out.c_str() + r.out.find("largest ", at), "largest %lf", &largest);
    EXPECT_LE(largest, 1e-3) << lane << "\n" << r.out;
  }
}

TEST(CmdCompareMatch, ABadMatchIsRefusedInOneLine) {
  const std::string dir = scratch_dir("compare_match_bad");
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--match", "speed"},
                                              std::vector<std::string>{"--match", "error", "-1"}}) {
    std::vector<std::string> args = bad;
    args.insert(args.end(), {"--video", dir + "/v.mp4"});
    const auto r = compare_small(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--match"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/v.mp4"));
  }
}

TEST(CmdCompareMatch, TheCoursesFixedPointAtStiffSpringsIsWrongNotOk) {
  // The case: ks = 2e7 on every spring, the course's one-iteration fixed point at the
  // scene's step. It stays finite, crumpled, held together by the post-step projection: WRONG by
  // the run's own verdict (over-stretched or energy made) or its distance from the reference.
  const std::string dir = scratch_dir("compare_wrong");
  const auto r = run_clothsim({"compare", kDrape, "--integrators", "implicit_euler_fixed_point,rk4", "--set",
                               "cloth.particles=[15,15]", "--set", "cloth.springs.structural.stiffness=2e7", "--set",
                               "cloth.springs.shear.stiffness=2e7", "--set", "cloth.springs.bend.stiffness=2e7",
                               "--duration", "0.5", "--match", "none", "--width", "320", "--height", "180",
                               "--still", "0.5", "-o", dir + "/still.png", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string fixed = row_of(r.out, "implicit_euler (fixed point)");
  EXPECT_NE(fixed.find("WRONG: "), std::string::npos) << r.out;
  EXPECT_EQ(fixed.find("ok to"), std::string::npos) << fixed;
  EXPECT_NE(row_of(r.out, "rk4").find("ok to t = 0.5 s"), std::string::npos) << r.out;
  const std::string json = cli::slurp(dir + "/s.json");
  EXPECT_NE(json.find("\"result\": \"WRONG: "), std::string::npos) << json;
  EXPECT_TRUE(fs::exists(dir + "/still.png"));
}

TEST(CmdCompareMatch, VaryMakesLanesByValueLabelledByTheAliasAndAGridWithIntegrators) {
  const std::string dir = scratch_dir("compare_vary");
  const auto r = compare_small({"--vary", "ks=2e3,2e5", "--integrators", "symplectic_euler,rk4", "--frames",
                                dir + "/f", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("drape: 4 lanes"), std::string::npos) << r.out;
  // Row by row: an integrator per row, a value per column; each lane its own scene.
  const std::string soft = row_of(r.out, "symplectic_euler, ks = 2000"), stiff = row_of(r.out, "rk4, ks = 2e5");
  ASSERT_FALSE(soft.empty()) << r.out;
  ASSERT_FALSE(stiff.empty()) << r.out;
  EXPECT_LT(r.out.find("symplectic_euler, ks = 2e5"), r.out.find("rk4, ks = 2000")) << r.out;
  // Softer springs stretch more: the strain numbers beneath the table say so.
  double soft_strain = 0.0, stiff_strain = 0.0;
  const auto strain_of = [&](const std::string& name) {
    const std::size_t at = r.out.find(name + " @ 0.0001 s: strain: largest ");
    double v = -1.0;
    if (at != std::string::npos) std::sscanf(r.out.c_str() + at + name.size() + 29, "%lf", &v);
    return v;
  };
  soft_strain = strain_of("symplectic_euler, ks = 2000");
  stiff_strain = strain_of("symplectic_euler, ks = 2e5");
  EXPECT_GT(soft_strain, 3.0 * stiff_strain) << r.out;
  EXPECT_TRUE(fs::exists(dir + "/f/symplectic_euler_ks=2000/frame_00000.png"));
  EXPECT_TRUE(fs::exists(dir + "/f/rk4_ks=2e5/frame_00006.png"));
}

TEST(CmdCompareMatch, VaryRefusesABadKeyOrErrorMatchingInOneLine) {
  const std::string dir = scratch_dir("compare_vary_bad");
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"--vary", "spheres.*.radius=1,2"}, std::vector<std::string>{"--vary", "ks"},
        std::vector<std::string>{"--vary", "ks=1,2", "--match", "error", "0.01"}}) {
    std::vector<std::string> args = bad;
    args.insert(args.end(), {"--video", dir + "/v.mp4"});
    const auto r = compare_small(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/v.mp4"));
  }
}

TEST(CmdCompareMatch, VaryLanesAreMatchedOnCostWhenAskedEachOnItsOwnScene) {
  // A grid of explicit and implicit Euler at two stiffnesses. At one step (the default under
  // --vary) every lane runs at the scene's; matched on cost, explicit Euler (the cheapest at the
  // scene's step) keeps it and each implicit lane runs where its Newton work, measured on its own
  // springs, costs the same per simulated second: the two stiffnesses' solves differ (at 2e6 N/m
  // the solve takes the sparse factor), so their steps do.
  const std::vector<std::string> grid{"--vary", "ks=2e3,2e6", "--integrators", "explicit_euler,implicit_euler"};
  std::vector<std::string> one_step = grid, matched = grid;
  one_step.insert(one_step.end(), {"--summary", scratch_dir("compare_vary_one_step") + "/s.json"});
  matched.insert(matched.end(), {"--match", "cost", "--summary", scratch_dir("compare_vary_cost") + "/s.json"});
  const auto at_one = compare_small(one_step), at_cost = compare_small(matched);
  ASSERT_EQ(at_one.exit_code, 0) << at_one.err;
  ASSERT_EQ(at_cost.exit_code, 0) << at_cost.err;
  EXPECT_DOUBLE_EQ(step_of(at_one.out, "implicit_euler, ks = 2000"), 1e-4) << at_one.out;
  EXPECT_DOUBLE_EQ(step_of(at_one.out, "implicit_euler, ks = 2e6"), 1e-4) << at_one.out;
  EXPECT_DOUBLE_EQ(step_of(at_cost.out, "explicit_euler, ks = 2000"), 1e-4) << at_cost.out;
  EXPECT_DOUBLE_EQ(step_of(at_cost.out, "explicit_euler, ks = 2e6"), 1e-4) << at_cost.out;
  const double soft = step_of(at_cost.out, "implicit_euler, ks = 2000"), stiff = step_of(at_cost.out, "implicit_euler, ks = 2e6");
  EXPECT_GT(soft, 1e-4) << at_cost.out;
  EXPECT_GT(stiff, 1e-4) << at_cost.out;
  EXPECT_GT(std::max(soft, stiff), 2.0 * std::min(soft, stiff))
      << "each lane's cost measured on its own springs, not the scene's\n" << at_cost.out;
  EXPECT_NE(at_cost.out.find("matched on cost by"), std::string::npos) << at_cost.out;
}

// Over --max-memory, compare is refused before its models or its pilots take anything: the
// estimate names the lanes at the steps they have before matching (implicit Euler at the
// scene's 1e-4 s, where matching on cost would give it 1/252 s). Nothing is written, not even
// the reference cache's folder.
TEST(CmdCompareMatch, ARunOverMaxMemoryIsRefusedBeforeTheStepsAreMatched) {
  const std::string dir = scratch_dir("compare_match_memory");
  // (the reference cache on, in a folder of its own: what it holds in memory is counted too)
  const cli::CliResult r = run_clothsim({"compare", kDrape, "--still", "1", "-o", dir + "/s.png", "--max-memory", "50M"},
                                        "env -u CLOTHSIM_REFERENCE_CACHE_MAX XDG_CACHE_HOME=" + dir + "/xdg");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("needs an estimated"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("implicit_euler@0.0001 "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("reference frames held for the cache"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir));
}
