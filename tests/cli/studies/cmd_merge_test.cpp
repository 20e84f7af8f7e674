// `clothsim merge` and --shard as users call them: parts joined into the single-process
// CSV; parts of other studies refused in one line naming the file (exit 2); missing and
// incomplete parts listed (exit 1), nothing written.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

namespace fs = std::filesystem;

std::string spring() { return std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml"; }

std::vector<std::string> study(const std::string& csv, const std::string& shard, const std::string& values = "100,400") {
  return {"stability", spring(), "--integrators", "symplectic_euler,rk4", "--values", values, "--duration", "20",
          "--min-dt", "0.01", "--max-dt", "0.5", "--jobs", "1", "--csv", csv, "--shard", shard};
}

// The CSV without its cpu_seconds column (the 8th), which measures the machine.
std::string untimed(const std::string& path) {
  std::string out;
  std::istringstream in(slurp(path));
  for (std::string line; std::getline(in, line);) {
    std::size_t a = 0;
    for (int i = 0; i < 7; ++i) a = line.find(',', a) + 1;
    out += line.substr(0, a) + line.substr(line.find(',', a) + 1) + "\n";
  }
  return out;
}

// A summary without its timing lines (cpu_seconds, wall_seconds: they measure the machine).
std::string untimed_json(const std::string& path) {
  std::istringstream in(slurp(path));
  std::string out;
  for (std::string line; std::getline(in, line);)
    if (line.find("\"cpu_seconds\"") == std::string::npos && line.find("\"wall_seconds\"") == std::string::npos)
      out += line + "\n";
  return out;
}

TEST(CmdMerge, JoinsShardsIntoWhatOneProcessWrites) {
  const std::string dir = scratch_dir("merge_join");
  for (const char* k : {"1/3", "2/3", "3/3"}) ASSERT_EQ(run_clothsim(study(dir + "/p.csv", k)).exit_code, 0) << k;
  std::vector<std::string> whole = study(dir + "/one.csv", "1/1");
  whole.resize(whole.size() - 2);  // without --shard
  ASSERT_EQ(run_clothsim(whole).exit_code, 0);
  const CliResult r = run_clothsim({"merge", dir + "/p.csv.shard-1-of-3", dir + "/p.csv.shard-2-of-3",
                                    dir + "/p.csv.shard-3-of-3", "--csv", dir + "/m.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(untimed(dir + "/m.csv"), untimed(dir + "/one.csv"));
}

TEST(CmdMerge, ARerunOfAShardRunsNothingItFinished) {
  const std::string dir = scratch_dir("merge_rerun");
  ASSERT_EQ(run_clothsim(study(dir + "/p.csv", "1/2")).exit_code, 0);
  const CliResult again = run_clothsim(study(dir + "/p.csv", "1/2"));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find(" finished before, 0 to run"), std::string::npos) << again.out;
  EXPECT_EQ(again.out.find(" 0 finished before"), std::string::npos) << again.out;
  const auto items = std::distance(fs::directory_iterator(dir + "/p.csv.shard-1-of-2/items"), fs::directory_iterator());
  EXPECT_GT(items, 0);
  EXPECT_EQ(line_count(slurp(dir + "/p.csv.shard-1-of-2/log")), items);  // one record per item, none twice
}

TEST(CmdMerge, RefusesShardsOfAnotherStudyNamingTheFile) {
  const std::string dir = scratch_dir("merge_refuse");
  ASSERT_EQ(run_clothsim(study(dir + "/a.csv", "1/2")).exit_code, 0);
  ASSERT_EQ(run_clothsim(study(dir + "/b.csv", "2/2", "100,500")).exit_code, 0);
  const CliResult r = run_clothsim({"merge", dir + "/a.csv.shard-1-of-2", dir + "/b.csv.shard-2-of-2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("b.csv.shard-2-of-2: a shard of a different study options"), std::string::npos) << r.err;
  const CliResult not_shard = run_clothsim({"merge", dir});
  EXPECT_EQ(not_shard.exit_code, 2);
  EXPECT_NE(not_shard.err.find("not a shard"), std::string::npos) << not_shard.err;
  // The same directory reused for a different study is refused before any work.
  const CliResult reuse = run_clothsim(study(dir + "/a.csv", "1/2", "100,600"));
  EXPECT_EQ(reuse.exit_code, 2);
  EXPECT_NE(reuse.err.find("holds a part of another study"), std::string::npos) << reuse.err;
}

TEST(CmdMerge, ListsMissingAndIncompleteShardsAndWritesNothing) {
  const std::string dir = scratch_dir("merge_missing");
  ASSERT_EQ(run_clothsim(study(dir + "/p.csv", "1/3")).exit_code, 0);
  ASSERT_EQ(run_clothsim(study(dir + "/p.csv", "3/3")).exit_code, 0);
  const std::string items = dir + "/p.csv.shard-3-of-3/items";
  fs::remove(fs::directory_iterator(items)->path());  // as if stopped before its last item
  const CliResult r = run_clothsim({"merge", dir + "/p.csv.shard-1-of-3", dir + "/p.csv.shard-3-of-3", "--csv",
                                    dir + "/m.csv"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing: shard 2/3 (" + dir + "/p.csv.shard-2-of-3)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("incomplete: " + dir + "/p.csv.shard-3-of-3"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/m.csv"));
}

TEST(CmdMerge, RefusesAnItemFileCutShortInOneLineAndWritesNothing) {
  const std::string dir = scratch_dir("merge_cut");
  ASSERT_EQ(run_clothsim(study(dir + "/p.csv", "1/1")).exit_code, 0);
  const fs::path item = fs::directory_iterator(dir + "/p.csv.shard-1-of-1/items")->path();
  fs::resize_file(item, fs::file_size(item) / 2);  // a copy cut short: the row would be lost
  const CliResult r = run_clothsim({"merge", dir + "/p.csv.shard-1-of-1", "--csv", dir + "/m.csv"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(item.string() + ": damaged"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/m.csv"));
  // A rerun of the shard redoes that item; the merge is then whole again.
  ASSERT_EQ(run_clothsim(study(dir + "/p.csv", "1/1")).exit_code, 0);
  const CliResult again = run_clothsim({"merge", dir + "/p.csv.shard-1-of-1", "--csv", dir + "/m.csv"});
  EXPECT_EQ(again.exit_code, 0) << again.err;
}

TEST(CmdMerge, RefusesAnOutputThatIsOneOfTheShardsFiles) {
  const std::string dir = scratch_dir("merge_own_input");
  ASSERT_EQ(run_clothsim(study(dir + "/p.csv", "1/1")).exit_code, 0);
  const std::string shard = dir + "/p.csv.shard-1-of-1";
  const std::string provenance = slurp(shard + "/provenance");
  const CliResult r = run_clothsim({"merge", shard, "--csv", shard + "/./provenance"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--csv " + shard + "/./provenance is a file of the shard"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(shard + "/provenance"), provenance);
}

TEST(CmdMerge, AMergedBenchChecksItsReferenceAsOneProcessDoes) {
  // The spring over a ground far below (projected contacts: the fixed-step RK4 reference) with
  // --reference-refinement 1: RK4 at the reference's own step is under 10x what halving the
  // reference moves it, well above round-off, so the reference cannot resolve it.
  const std::string dir = scratch_dir("merge_bench_reference");
  const std::vector<std::string> args{"bench", spring(), "--set", "ground={height: -5}", "--integrators", "rk4",
                                      "--dts", "0.01,0.005", "--duration", "1", "--reference-refinement", "1"};
  std::vector<std::string> one = args;
  one.insert(one.end(), {"--csv", dir + "/one.csv", "--summary", dir + "/one.json"});
  const CliResult whole = run_clothsim(one);
  ASSERT_EQ(whole.exit_code, 1) << whole.err;
  for (const char* k : {"1/2", "2/2"}) {
    std::vector<std::string> part = args;
    part.insert(part.end(), {"--csv", dir + "/p.csv", "--shard", k});
    ASSERT_EQ(run_clothsim(part).exit_code, 0) << k;
  }
  const CliResult r = run_clothsim({"merge", dir + "/p.csv.shard-1-of-2", dir + "/p.csv.shard-2-of-2", "--csv",
                                    dir + "/m.csv", "--summary", dir + "/m.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("the reference is not converged"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/m.csv"));
  EXPECT_NE(slurp(dir + "/m.json").find("\"converged\": false"), std::string::npos);
  EXPECT_EQ(untimed_json(dir + "/m.json"), untimed_json(dir + "/one.json"));
}

TEST(CmdMerge, TheMergedSummaryIsWhatOneProcessWritesButForTiming) {
  const std::string dir = scratch_dir("merge_summary");
  std::vector<std::string> stab = study(dir + "/s.csv", "1/1");
  stab[3] = "symplectic_euler,rk4,implicit_euler";  // implicit_euler's frame_steps too
  std::vector<std::string> bench{"bench", spring(), "--integrators", "symplectic_euler,rk4", "--dts", "0.01,0.02",
                                 "--duration", "2", "--jobs", "1", "--csv", dir + "/b.csv", "--shard", "1/1"};
  for (std::vector<std::string> args : {stab, bench}) {
    const std::string csv = args[args.size() - 3];
    for (const char* k : {"1/2", "2/2"}) {
      args.back() = k;
      ASSERT_EQ(run_clothsim(args).exit_code, 0) << csv << " " << k;
    }
    args.resize(args.size() - 4);  // one process: without --csv and --shard
    args.insert(args.end(), {"--summary", csv + ".one.json"});
    ASSERT_EQ(run_clothsim(args).exit_code, 0) << csv;
    const CliResult m = run_clothsim({"merge", csv + ".shard-1-of-2", csv + ".shard-2-of-2", "--summary", csv + ".json"});
    ASSERT_EQ(m.exit_code, 0) << m.err;
    EXPECT_EQ(untimed_json(csv + ".json"), untimed_json(csv + ".one.json")) << csv;
    EXPECT_NE(untimed_json(csv + ".json").find("\"complete\": true"), std::string::npos);
  }
}

TEST(CmdMerge, AShardNeedsACsvAndLeavesThePlotToMerge) {
  const std::string dir = scratch_dir("merge_options");
  std::vector<std::string> no_csv = study("", "1/2");
  no_csv.erase(no_csv.end() - 4, no_csv.end() - 2);
  const CliResult a = run_clothsim(no_csv);
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_NE(a.err.find("--shard: needs --csv"), std::string::npos) << a.err;
  std::vector<std::string> bad = study(dir + "/p.csv", "3/2");
  EXPECT_EQ(run_clothsim(bad).exit_code, 2);
  bad = study(dir + "/p.csv", "auto");
  const CliResult b = run_clothsim(bad, "env -u SLURM_ARRAY_TASK_ID ");
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("SLURM_ARRAY_TASK_ID"), std::string::npos) << b.err;
  EXPECT_FALSE(fs::exists(dir + "/p.csv.shard-1-of-2"));
}

}  // namespace
}  // namespace clothsim::testing
