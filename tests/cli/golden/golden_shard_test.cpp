// `golden check --shard K/N` and `clothsim merge`: the parts of a manifest's check, joined,
// report what one check reports (its lines, CSV and summary, timing aside) and fail as it
// fails: an image that differs in any part fails the merge, naming its manifest entry.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {
namespace fs = std::filesystem;

// A user's directory: the drape and the spring, three entries, their goldens written.
struct ShardedProject {
  std::string dir, manifest;
  explicit ShardedProject(const std::string& name) : dir(scratch_dir(name)), manifest(dir + "/goldens.yaml") {
    for (const char* scene : {"drape.yaml", "spring.yaml"})
      fs::copy_file(std::string(CLOTHSIM_SCENES_DIR) + "/" + scene, dir + "/" + scene);
    std::ofstream(manifest) << "size: [96, 54]\ngoldens:\n"
                               "  - scene: drape.yaml\n    times: [0.05, 0.1]\n"
                               "  - scene: spring.yaml\n    times: [0.5]\n"
                               "  - scene: drape.yaml\n    name: drape_rk4\n    integrator: rk4\n    times: [0.05]\n";
  }
  CliResult shard(const std::string& k) const {
    return run_clothsim({"golden", "check", manifest, "--csv", dir + "/p.csv", "--shard", k});
  }
  std::string part(int k) const { return dir + "/p.csv.shard-" + std::to_string(k) + "-of-2"; }
};

// The report's lines (ok/FAIL and the tally), without the shard's and merge's own.
std::string report_lines(const std::string& out) {
  std::istringstream in(out);
  std::string lines;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("ok ", 0) == 0 || line.rfind("FAIL ", 0) == 0 || line.rfind("golden: ", 0) == 0) lines += line + "\n";
  return lines;
}

// The summary without its cpu_seconds lines (they measure the machine).
std::string untimed_json(const std::string& path) {
  std::istringstream in(slurp(path));
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (line.find("\"cpu_seconds\"") == std::string::npos) out += line + "\n";
  return out;
}

TEST(GoldenShard, MergedPartsReportWhatOneCheckReports) {
  const ShardedProject p("golden_shard_join");
  ASSERT_EQ(run_clothsim({"golden", "update", p.manifest}).exit_code, 0);
  const CliResult one = run_clothsim({"golden", "check", p.manifest, "--csv", p.dir + "/one.csv", "--summary",
                                      p.dir + "/one.json"});
  ASSERT_EQ(one.exit_code, 0) << one.out << one.err;
  const CliResult a = p.shard("1/2"), b = p.shard("2/2");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_NE(a.out.find("shard 1/2 of golden: 1 of 3 items"), std::string::npos) << a.out;  // split by cost
  const CliResult m = run_clothsim({"merge", p.part(1), p.part(2), "--csv", p.dir + "/m.csv", "--summary",
                                    p.dir + "/m.json"});
  ASSERT_EQ(m.exit_code, 0) << m.out << m.err;
  EXPECT_EQ(report_lines(m.out), report_lines(one.out));
  EXPECT_NE(m.out.find("golden: 4 of 4 images match"), std::string::npos) << m.out;
  EXPECT_EQ(slurp(p.dir + "/m.csv"), slurp(p.dir + "/one.csv"));
  EXPECT_EQ(line_count(slurp(p.dir + "/m.csv")), 5);
  EXPECT_EQ(untimed_json(p.dir + "/m.json"), untimed_json(p.dir + "/one.json"));
  EXPECT_NE(slurp(p.dir + "/m.json").find("\"command\": \"golden\""), std::string::npos);
}

TEST(GoldenShard, AFailedImageInAnyPartFailsTheMergeNamingTheEntry) {
  ShardedProject p("golden_shard_fail");
  ASSERT_EQ(run_clothsim({"golden", "update", p.manifest}).exit_code, 0);
  std::string drape = slurp(p.dir + "/drape.yaml");  // a bigger ball: the cloth drapes differently
  drape.replace(drape.find("radius: 1.0"), 11, "radius: 1.4");
  std::ofstream(p.dir + "/drape.yaml") << drape;
  // A part whose image differs still succeeds (the array's merge job must run) ...
  ASSERT_EQ(p.shard("1/2").exit_code, 0);
  const CliResult missing = run_clothsim({"merge", p.part(1)});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("missing: shard 2/2 (" + p.part(2) + ")"), std::string::npos) << missing.err;
  ASSERT_EQ(p.shard("2/2").exit_code, 0);
  // ... and the merge fails, naming it.
  const CliResult m = run_clothsim({"merge", p.part(1), p.part(2)});
  EXPECT_EQ(m.exit_code, 1) << m.out << m.err;
  EXPECT_NE(m.out.find("FAIL  drape_rk4_t50ms.png"), std::string::npos) << m.out;
  EXPECT_NE(m.out.find("golden: 1 of 4 images match"), std::string::npos) << m.out;
  EXPECT_EQ(line_count(m.err), 1) << m.err;
  EXPECT_NE(m.err.find("failed: goldens[0] (drape_t50ms.png), goldens[0] (drape_t100ms.png), goldens[2] "
                       "(drape_rk4_t50ms.png)"),
            std::string::npos)
      << m.err;
  EXPECT_TRUE(fs::exists(p.dir + "/drape_rk4_t50ms.actual.png"));
}

TEST(GoldenShard, APartOfAnotherManifestOrSceneIsRefused) {
  ShardedProject p("golden_shard_refuse");
  ASSERT_EQ(p.shard("1/2").exit_code, 0);
  std::ofstream(p.dir + "/drape.yaml", std::ios::app) << "# edited\n";  // a scene the manifest names
  const CliResult again = p.shard("1/2");
  EXPECT_EQ(again.exit_code, 2) << again.out;
  EXPECT_NE(again.err.find("holds a part of another study"), std::string::npos) << again.err;
  const CliResult summary = run_clothsim({"golden", "check", p.manifest, "--csv", p.dir + "/q.csv", "--shard", "1/2",
                                          "--summary", p.dir + "/q.json"});
  EXPECT_EQ(summary.exit_code, 2);
  EXPECT_NE(summary.err.find("give --summary to clothsim merge"), std::string::npos) << summary.err;
}

}  // namespace
}  // namespace clothsim::testing
