// One lane grammar at every door (scene/lane.h): the same strings through `run --integrator`,
// the scene's `integrator:` key, `compare --integrators`, `bench` and `stability`, each door
// running exactly the lane the string says. (Python's Simulation(lane=...) runs them in
// tests/python/test_clothsim.py; the grammar itself is tests/scene/lane_test.cpp.)
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

const char* kSheet = R"(name: lanes
duration: 0.05
dt: 1e-3
cloth:
  particles: [5, 5]
  size: [1, 1]
  center: [0, 1, 0]
  plane: xz
  particle_mass: 0.04
  springs:
    structural: {stiffness: 500, damping: 1}
    shear: {stiffness: 500, damping: 1}
  pinned: [[0, 0], [4, 0]]
)";

// The lanes, each as typed and as the program spells it back (--summary's "lane").
struct Typed {
  const char* text;
  const char* spelt;
};
const std::vector<Typed> kLanes{
    {"rk4@2e-4", "rk4@2e-4"},
    {"xpbd@1/60:5", "xpbd@1/60:5"},
    {"vbd@1/100:tol=1e-4", "vbd@1/100:tol=0.0001"},
    {"implicit_euler@1/60:1", "implicit_euler@1/60:1"},
    {"implicit_euler_fixed_point@5e-4", "implicit_euler_fixed_point@5e-4"},
    {" projective_dynamics @ 1/200 : 4 ", "projective_dynamics@1/200:4"},
    {"dopri5@1e-3:tol=1e-6", "dopri5@1e-3:tol=1e-06"},
    {"newmark@1/60:beta=0.3:gamma=0.6", "newmark@1/60:beta=0.3:gamma=0.6"},
    {"generalized_alpha@1/60:rho=0.5", "generalized_alpha@1/60:rho=0.5"},
    {"bdf2@1/60", "bdf2@1/60"},
    {"rkf78@1e-3:rtol=1e-8:atol=1e-6", "rkf78@1e-3:rtol=1e-08:atol=1e-06"},
};

std::string write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(LaneDoors, RunAndTheScenesKeyRunTheSameLaneToTheLastBit) {
  const std::string dir = scratch_dir("lane_doors_run");
  const std::string scene = write(dir + "/sheet.yaml", kSheet);
  for (const Typed& lane : kLanes) {
    const CliResult by_option = run_clothsim({"run", scene, "--integrator", lane.text, "--state", dir + "/a.csv"});
    ASSERT_EQ(by_option.exit_code, 0) << lane.text << ": " << by_option.err;
    // The same lane in the file: the file's dt goes, since the lane gives the step.
    std::string text = kSheet;
    text.replace(text.find("dt: 1e-3\n"), 9, std::string("integrator: \"") + lane.text + "\"\n");
    const std::string keyed = write(dir + "/keyed.yaml", text);
    const CliResult by_key = run_clothsim({"run", keyed, "--state", dir + "/b.csv"});
    ASSERT_EQ(by_key.exit_code, 0) << lane.text << ": " << by_key.err;
    EXPECT_EQ(slurp(dir + "/a.csv"), slurp(dir + "/b.csv")) << lane.text;
  }
}

TEST(LaneDoors, CompareRunsEachLaneAndSpellsItBack) {
  const std::string dir = scratch_dir("lane_doors_compare");
  const std::string scene = write(dir + "/sheet.yaml", kSheet);
  for (const Typed& lane : kLanes) {
    const CliResult r = run_clothsim({"compare", scene, "--integrators", std::string(lane.text) + ",symplectic_euler",
                                      "--summary", dir + "/s.json", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << lane.text << ": " << r.err;
    EXPECT_NE(slurp(dir + "/s.json").find(std::string("\"lane\": \"") + lane.spelt + "\""), std::string::npos)
        << lane.text << "\n" << slurp(dir + "/s.json");
  }
}

TEST(LaneDoors, TheStudiesTakeTheLanesWithoutTheirStepAndSayWhyNotWithIt) {
  const std::string dir = scratch_dir("lane_doors_studies");
  const std::string scene = write(dir + "/sheet.yaml", kSheet);
  for (const char* stepless : {"xpbd:5", "vbd:tol=1e-4", "implicit_euler:1", "implicit_euler_fixed_point"}) {
    const CliResult bench = run_clothsim({"bench", scene, "--integrators", stepless, "--dts", "1e-3,5e-4",
                                          "--duration", "0.02", "--csv", dir + "/b.csv", "--quiet"});
    EXPECT_EQ(bench.exit_code, 0) << stepless << ": " << bench.err;
    const CliResult stability = run_clothsim({"stability", scene, "--integrators", stepless, "--values", "500",
                                              "--duration", "0.02", "--csv", dir + "/s.csv", "--quiet"});
    EXPECT_EQ(stability.exit_code, 0) << stepless << ": " << stability.err;
  }
  const CliResult adaptive = run_clothsim({"stability", scene, "--integrators", "dopri5:tol=1e-6"});
  EXPECT_EQ(adaptive.exit_code, 2);
  EXPECT_NE(adaptive.err.find("--integrators: 'dopri5:tol=1e-06': stability searches the largest stable step"),
            std::string::npos) << adaptive.err;
  const CliResult with_step = run_clothsim({"bench", scene, "--integrators", "xpbd@1/60:5"});
  EXPECT_EQ(with_step.exit_code, 2);
  EXPECT_NE(with_step.err.find("--integrators: 'xpbd@1/60:5': bench sweeps the step"), std::string::npos) << with_step.err;
}

TEST(LaneDoors, EveryDoorRefusesABadLaneWithTheSameReason) {
  const std::string dir = scratch_dir("lane_doors_refusals");
  const std::string scene = write(dir + "/sheet.yaml", kSheet);
  const std::string why = "rk4 has no iterations to set (in 'rk4:3')";
  const CliResult run = run_clothsim({"run", scene, "--integrator", "rk4:3"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--integrator: " + why), std::string::npos) << run.err;
  const CliResult compare = run_clothsim({"compare", scene, "--integrators", "rk4:3", "--summary", dir + "/s.json"});
  EXPECT_EQ(compare.exit_code, 2);
  EXPECT_NE(compare.err.find("--integrators: " + why), std::string::npos) << compare.err;
  std::string text = kSheet;
  text.insert(0, "integrator: \"rk4:3\"\n");
  const CliResult key = run_clothsim({"run", write(dir + "/bad.yaml", text)});
  EXPECT_EQ(key.exit_code, 2);
  EXPECT_NE(key.err.find("bad.yaml:1: integrator: " + why), std::string::npos) << key.err;
  const CliResult twice = run_clothsim({"run", scene, "--integrator", "rk4@1e-4", "--dt", "1e-3"});
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("gives the step, and so does --dt"), std::string::npos) << twice.err;
}

TEST(LaneDoors, HelpListsEveryLaneName) {
  const CliResult r = run_clothsim({"run", "--help"});
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("implicit_euler_fixed_point"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vbd@1/60:10"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace clothsim::testing

namespace clothsim::testing {
namespace {

TEST(LaneDoors, AnAdaptiveLaneSaysWhatItsErrorControlDid) {
  const std::string dir = scratch_dir("lane_doors_adaptive");
  const std::string scene = std::string(CLOTHSIM_SCENES_DIR) + "/drape_smooth.yaml";
  const CliResult r = run_clothsim({"compare", scene, "--integrators", "dopri5:tol=1e-4,bs3:tol=1e-4", "--duration",
                                    "0.3", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("steps of dopri5:tol=0.0001: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" refused by its error control"), std::string::npos) << r.out;
  const std::string summary = slurp(dir + "/s.json");
  for (const char* key : {"\"rejected_steps\"", "\"smallest_step\"", "\"largest_step\"", "\"rtol\": 0.0001"})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  // On the course's drape the projection is a jump its error control never sees: it says so.
  const CliResult projected = run_clothsim({"run", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--integrator",
                                            "dopri5:tol=1e-4", "--duration", "0.3"});
  ASSERT_EQ(projected.exit_code, 0) << projected.err;
  EXPECT_NE(projected.out.find("which the error control does not see"), std::string::npos) << projected.out;
}

}  // namespace
}  // namespace clothsim::testing
