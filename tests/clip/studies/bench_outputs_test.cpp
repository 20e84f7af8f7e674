// bench's files (src/clip/studies/bench_outputs.h), written the same by the CLI and the Python
// module: a shard's journaled rows are the whole study's rows, a stopped study keeps and names
// what finished, --vary's values stack under one header, and an unresolved error is no number.
#include "clip/studies/bench_outputs.h"

#include <gtest/gtest.h>

#include <fstream>

#include "cli/cli_process.h"
#include "clip/studies/csv_rows.h"
#include "clip/common/cli_common.h"
#include "clip/merge/study_merge.h"
#include "clip/studies/study_shard.h"
#include "core/integrators/integrator_kind.h"
#include "scene/scene_parser.h"
#include "test_support.h"

namespace clothsim::clip {
namespace {

using testing::scratch_dir;

// A small work-precision study of the damped spring: rk4 and midpoint at three steps to 0.2 s.
BenchOptions small_bench() {
  BenchOptions o;
  o.scene.path = testing::scene_path("spring.yaml");
  o.integrators = "midpoint,rk4";
  o.dts = "0.01,0.005,0.0025";
  o.frame_dts = "none";
  o.scene.duration = 0.2;
  o.jobs = 1;
  return o;
}

// A CSV's rows without its measured times.
std::vector<std::vector<std::string>> without_times(const std::string& text) {
  return testing::csv_rows_without(text, {"wall_seconds", "cpu_seconds"});
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(BenchShard, JournalsTheWholeStudysRowsAndARerunRunsNothing) {
  BenchOptions o = small_bench();
  SceneDef scene = load_scene(o.scene.path, {});
  scene.duration = *o.scene.duration;
  const std::vector<Lane> lanes = bench_lanes(o, scene);
  const BenchModels models(o, scene, lanes, plan_bench(o, scene, lanes));
  const WorkPrecisionResult whole = analysis::work_precision(models.model, models.spec, {});
  const std::string whole_csv = written_text([&](std::FILE* f) { write_bench_csv(f, whole, models.spec.lane_names); });

  o.csv = scratch_dir("bench_outputs_shard") + "/wp.csv";
  o.shard = "1/1";
  EXPECT_EQ(bench_shard(o, models.model, models.spec, models.spec.lane_names, {}), 0);
  const std::string dir = shard_dir(o.csv, {1, 1});
  EXPECT_EQ(without_times(merged_csv({read_part(dir)})), without_times(whole_csv))
      << "a run in a shard is the same run, measured against the same reference";
  // The order shows in the rows: rk4's error falls about 16x per halving of the step.
  const std::vector<std::vector<std::string>> rows = without_times(whole_csv);
  ASSERT_EQ(rows.size(), 1u + 2 * 3);
  // A rerun of the same part finds every item journaled and runs none.
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(bench_shard(o, models.model, models.spec, models.spec.lane_names, {}), 0);
  EXPECT_NE(::testing::internal::GetCapturedStdout().find("6 finished before, 0 to run"), std::string::npos);
}

TEST(WriteBenchOutputs, KeepsAStoppedStudysFinishedRunsAndNamesThemIncomplete) {
  BenchOptions o = small_bench();
  o.csv = scratch_dir("bench_outputs_stopped") + "/wp.csv";
  o.summary = scratch_dir("bench_outputs_stopped_json") + "/wp.json";
  WorkPrecisionResult r;
  r.duration = 0.2;
  r.complete = false;  // stopped after one run of six
  analysis::WorkPrecisionPoint p;
  p.integrator = *parse_integrator("rk4");
  p.dt = 0.01, p.steps = 20, p.finished = true, p.rms_error = 1e-6, p.max_error = 2e-6;
  r.points = {p};
  try {
    write_bench_outputs(o, "spring.yaml", "spring", r, {"rk4"}, 6, nullptr);
    FAIL() << "a stopped study is a failure";
  } catch (const RuntimeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("1 of 6 runs finished; kept " + o.csv + " (incomplete)"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(without_times(read_text(o.csv)).size(), 2u) << "the header and the one run that finished";
  EXPECT_NE(read_text(o.summary).find("\"complete\": false"), std::string::npos);
}

TEST(RunLaneJson, HidesAnUnresolvedErrorAndNamesALaneWithItsIterations) {
  analysis::WorkPrecisionPoint p;
  p.integrator = *parse_integrator("xpbd");
  p.dt = 0.01, p.steps = 10, p.finished = true, p.rms_error = 1e-9, p.unresolved = true;
  const std::string json = run_lane_json("drape", p, {"xpbd:10"}).dump();
  EXPECT_NE(json.find("\"rms_error\": null"), std::string::npos) << json;  // under the reference's error: no number
  EXPECT_NE(json.find("\"lane\": \"xpbd:10\""), std::string::npos) << json;
  p.unresolved = false;
  EXPECT_EQ(run_lane_json("drape", p, {"xpbd"}).dump().find("\"lane\""), std::string::npos) << "the plain name is enough";
}

TEST(ValuesTable, StacksEachValuesRowsUnderOneHeaderInValueOrder) {
  std::vector<ValueStudy> studies(2);
  for (std::size_t v = 0; v < studies.size(); ++v) {
    studies[v].names = {v == 0 ? "rk4 (ks = 100)" : "rk4 (ks = 400)"};
    analysis::WorkPrecisionPoint p;
    p.integrator = *parse_integrator("rk4");
    p.dt = 0.01 * static_cast<double>(v + 1);
    studies[v].result.points = {p};
  }
  const analysis::CsvTable t = values_table(studies);
  EXPECT_EQ(t.header(), analysis::work_precision_table({}, {}).header());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0][0].text, "rk4 (ks = 100)");
  EXPECT_EQ(t.rows[1][0].text, "rk4 (ks = 400)");
}

TEST(BenchPlotTitle, SaysTheNumbersInThreeFigures) {
  // It printed "reference error 1.1274976125260227e-12 m RMS".
  WorkPrecisionResult r;
  r.duration = 0.2;
  r.reference.finished = true;
  r.reference.change_rms = 1.1274976125260227e-12;
  EXPECT_EQ(bench_plot_title("spring", r), "spring (T = 0.2 s; reference error 1.13e-12 m RMS)");
  r.duration = 1.0 / 3.0;
  r.reference.finished = false;
  EXPECT_EQ(bench_plot_title("spring", r), "spring (T = 0.333 s; reference error unknown m RMS)");
}

}  // namespace
}  // namespace clothsim::clip
