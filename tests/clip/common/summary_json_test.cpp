// --summary FILE.json of run, compare, bench, stability and golden check: each parses (Python's json
// module, as a script reading it would) and has the fields docs/summary.md lists, with the
// run's true figures; and JsonObject's output is JSON (escapes, NaN as null, nesting).
#include "clip/common/summary_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {

// Parses PATH as a `command` summary with `lanes` lanes, checks every documented key, and
// prints each lane as [integrator, dt, steps, force_evaluations, diverged_at] (JSON).
const char* const kCheckScript = R"(
import json, sys
path, command, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
d = json.load(open(path))
common = ["scene", "integrator", "dt", "steps", "force_evaluations", "cpu_seconds",
          "newton_iterations", "cg_iterations", "factorizations", "unconverged_steps", "diverged_at"]
lane_keys = {"run": ["t_reached", "max_residual"], "compare": ["t_reached"],
             "bench": ["wall_seconds", "rms_error", "max_error"],
             "stability": ["value", "outcome", "stable_dt", "unstable_dt", "failure", "reason", "trials",
                           "w_max", "dt_springs", "dt_with_damping", "frame_steps"],
             "golden": ["entry", "name", "images"]}
top_keys = {"bench": ["duration", "complete", "reference"], "stability": ["param", "duration", "min_dt", "max_dt", "complete"],
            "golden": ["complete", "images", "matching"]}
for k in ["clothsim", "command", "source", "lanes"] + top_keys.get(command, []):
    assert k in d, "missing top-level key " + k
assert d["command"] == command, d["command"]
assert len(d["lanes"]) == n, len(d["lanes"])
for lane in d["lanes"]:
    for k in common + lane_keys[command]:
        assert k in lane, "missing lane key " + k
print(json.dumps([[l["integrator"], l["dt"], l["steps"], l["force_evaluations"], l["diverged_at"]] for l in d["lanes"]]))
)";

std::string check_summary(const std::string& path, const std::string& command, int lanes) {
  // Beside the summary, not in a shared place: CTest runs these tests in parallel.
  const std::string script = path + ".check.py";
  std::ofstream(script) << kCheckScript;
  const std::string out = path + ".check.out";
  const std::string cmd = "python3 " + shell_quote(script) + " " + shell_quote(path) + " " + command + " " +
                          std::to_string(lanes) + " >" + shell_quote(out) + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::string text = slurp(out);
  if (status != 0) ADD_FAILURE() << path << ": " << text;
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

std::string spring() { return std::string(CLOTHSIM_SCENES_DIR) + "/spring.yaml"; }

TEST(SummaryJson, RunWritesOneLaneWithItsFigures) {
  const std::string dir = scratch_dir("summary_run");
  const CliResult r = run_clothsim({"run", spring(), "--duration", "0.5", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(check_summary(dir + "/s.json", "run", 1), R"([["symplectic_euler", 0.001, 500, 500, null]])");
}

TEST(SummaryJson, ADivergedRunSaysWhen) {
  const std::string dir = scratch_dir("summary_diverged");
  const CliResult r = run_clothsim({"run", spring(), "--set", "cloth.springs.structural.damping=0", "--integrator",
                                    "explicit_euler", "--dt", "0.1", "--duration", "100", "--summary", dir + "/s.json"});
  ASSERT_EQ(r.exit_code, 3) << r.err;
  const std::string lanes = check_summary(dir + "/s.json", "run", 1);
  EXPECT_EQ(lanes.rfind(R"([["explicit_euler", 0.1, )", 0), 0u) << lanes;
  EXPECT_EQ(lanes.find("null]]"), std::string::npos) << lanes;  // diverged_at is a time
}

TEST(SummaryJson, CompareWritesOneLanePerIntegrator) {
  const std::string dir = scratch_dir("summary_compare");
  const CliResult r = run_clothsim({"compare", spring(), "--duration", "0.2", "--integrators", "rk4,implicit_euler",
                                    "--match", "none", "--summary", dir + "/c.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(check_summary(dir + "/c.json", "compare", 2),
            R"([["rk4", 0.001, 200, 800, null], ["implicit_euler", 0.001, 200, 385, null]])");
}

TEST(SummaryJson, BenchWritesOneLanePerRun) {
  const std::string dir = scratch_dir("summary_bench");
  const CliResult r = run_clothsim({"bench", spring(), "--integrators", "symplectic_euler,rk4", "--dts", "0.01,0.005",
                                    "--duration", "1", "--summary", dir + "/b.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(check_summary(dir + "/b.json", "bench", 4),
            R"([["symplectic_euler", 0.005, 200, 200, null], ["symplectic_euler", 0.01, 100, 100, null], )"
            R"(["rk4", 0.005, 200, 800, null], ["rk4", 0.01, 100, 400, null]])");
}

TEST(SummaryJson, StabilityWritesOneLanePerSearch) {
  const std::string dir = scratch_dir("summary_stability");
  const CliResult r = run_clothsim({"stability", spring(), "--set", "cloth.springs.structural.damping=0",
                                    "--integrators", "symplectic_euler", "--values", "100,400", "--duration", "400",
                                    "--min-dt", "0.02", "--max-dt", "1", "--summary", dir + "/st.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string lanes = check_summary(dir + "/st.json", "stability", 2);
  EXPECT_EQ(lanes.rfind(R"([["symplectic_euler", 0.)", 0), 0u) << lanes;  // the largest stable dt
}

TEST(SummaryJson, GoldenCheckWritesOneLanePerEntry) {
  const std::string dir = scratch_dir("summary_golden");
  std::ofstream(dir + "/m.yaml") << "size: [64, 36]\ngoldens:\n  - scene: " << spring() << "\n    times: [0.1, 0.2]\n";
  const CliResult r = run_clothsim({"golden", "check", dir + "/m.yaml", "--summary", dir + "/g.json"});
  ASSERT_EQ(r.exit_code, 1) << r.err;  // no golden images yet: both missing
  const std::string lanes = check_summary(dir + "/g.json", "golden", 1);
  EXPECT_EQ(lanes.rfind(R"([["symplectic_euler", )", 0), 0u) << lanes;
  EXPECT_NE(slurp(dir + "/g.json").find("\"matching\": 0"), std::string::npos);
}

TEST(SummaryJson, AnUnwritableSummaryFailsBeforeAnyWork) {
  const std::string dir = clothsim::testing::scratch_dir("summary_unwritable");
  std::ofstream(dir + "/plain") << "x";  // a file where its folder would have to be made
  const CliResult r = run_clothsim({"run", spring(), "--summary", dir + "/plain/dir/s.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_EQ(r.out, "");
}

TEST(JsonObject, AnObjectDumpedEarlierIsPlacedAsIfBuiltInPlace) {
  clip::JsonObject inner;
  inner.integer("n", 3).array("list", {clip::JsonObject().number("x", 0.5)});
  clip::JsonObject built, restored;
  built.text("a", "b").array("lanes", {inner, inner});
  restored.text("a", "b").array("lanes", {clip::JsonObject::from_dump(inner.dump()), clip::JsonObject::from_dump(inner.dump() + "\n")});
  EXPECT_EQ(restored.dump(), built.dump());
}

TEST(JsonObject, WritesEscapedTextNullForNonFiniteAndNesting) {
  clip::JsonObject inner;
  inner.integer("n", 3).boolean("ok", true);
  clip::JsonObject o;
  o.text("reason", "a \"quoted\"\\ line\nand\ttab")
      .number("x", 0.1)
      .number("nan", NAN)
      .number("missing", std::optional<double>())
      .object("inner", inner)
      .array("empty", {})
      .array("list", {inner, inner});
  EXPECT_EQ(o.dump(),
            "{\n"
            "  \"reason\": \"a \\\"quoted\\\"\\\\ line\\nand\\ttab\",\n"
            "  \"x\": 0.10000000000000001,\n"
            "  \"nan\": null,\n"
            "  \"missing\": null,\n"
            "  \"inner\": {\n    \"n\": 3,\n    \"ok\": true\n  },\n"
            "  \"empty\": [],\n"
            "  \"list\": [\n"
            "    {\n      \"n\": 3,\n      \"ok\": true\n    },\n"
            "    {\n      \"n\": 3,\n      \"ok\": true\n    }\n"
            "  ]\n"
            "}");
}

}  // namespace
}  // namespace clothsim::testing
