// stability's files (src/clip/studies/stability_outputs.h), written the same by the CLI and the
// Python module: a shard's journaled rows are the whole sweep's, a search's lane carries its
// bracket beside the estimate, and a stopped sweep keeps and names what finished.
#include "clip/studies/stability_outputs.h"

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

// The undamped spring at two stiffnesses whose limits lie inside the range tried, symplectic
// Euler only, searched to 10 %.
StabilityOptions small_sweep() {
  StabilityOptions o;
  o.scene.path = testing::scene_path("spring.yaml");
  o.integrators = "symplectic_euler";
  o.scene.sets = {"cloth.springs.structural.damping=0"};
  o.values = "1e6,4e6";
  o.precision = 0.1;
  o.frame_dts = "none";
  o.jobs = 1;
  return o;
}

// A CSV's lines without its cpu_seconds column.
std::vector<std::vector<std::string>> without_cpu(const std::string& text) {
  return testing::csv_rows_without(text, {"cpu_seconds"});
}

TEST(StabilityShard, JournalsTheWholeSweepsRowsAndALanePerSearch) {
  StabilityOptions o = small_sweep();
  StabilityStudy study = plan_stability(o, load_scene(o.scene.path, o.scene.sets));
  const std::vector<analysis::StabilityCase> refs = study.refs();
  const std::vector<analysis::StabilityLimit> limits = analysis::stability_sweep(refs, study.spec, {});
  ASSERT_EQ(limits.size(), 2u);
  // Four times the stiffness, half the limit (2/w, w = sqrt(k/m)): the search sees the physics.
  ASSERT_EQ(limits[1].outcome, analysis::StabilityOutcome::Bracketed);
  EXPECT_NEAR(limits[1].stable_dt / limits[0].stable_dt, 0.5, 0.5 * 2 * o.precision);
  const std::string whole = written_text([&](std::FILE* f) { write_stability_csv(f, o.param, limits, study.spec, study.names); });

  o.csv = scratch_dir("stability_outputs_shard") + "/st.csv";
  o.shard = "1/1";
  EXPECT_EQ(stability_shard(o, "spring", refs, study.spec, study.names, {}), 0);
  const ShardPart part = read_part(shard_dir(o.csv, {1, 1}));
  EXPECT_EQ(without_cpu(merged_csv({part})), without_cpu(whole));
  EXPECT_EQ(merged_lanes({part}).size(), 2u) << "each search's lane for merge --summary";
}

TEST(SearchLaneJson, CarriesTheBracketTheFailureAndTheEstimate) {
  analysis::StabilityLimit l;
  l.integrator = *parse_integrator("symplectic_euler");
  l.value = 400;
  l.outcome = analysis::StabilityOutcome::Bracketed;
  l.stable_dt = 0.125, l.unstable_dt = 0.25;
  l.failure = analysis::Failure::Diverged;
  const std::string json = search_lane_json("spring", l, {"symplectic_euler"}).dump();
  for (const char* key : {"\"stable_dt\": 0.125", "\"unstable_dt\": 0.25", "\"failure\": \"diverged\"", "\"value\": 400",
                          "\"dt_springs\""})
    EXPECT_NE(json.find(key), std::string::npos) << key << " in " << json;
}

TEST(WriteStabilityOutputs, KeepsAStoppedSweepsSearchesAndNamesThemIncomplete) {
  StabilityOptions o = small_sweep();
  const SceneDef base = load_scene(o.scene.path, o.scene.sets);
  StabilityStudy study = plan_stability(o, base);
  o.csv = scratch_dir("stability_outputs_stopped") + "/st.csv";
  analysis::StabilityLimit l;
  l.integrator = study.spec.integrators[0];
  l.value = 1e6;
  try {
    write_stability_outputs(o, base, {l}, study, nullptr);  // one of two searches
    FAIL() << "a stopped sweep is a failure";
  } catch (const RuntimeFailure& e) {
    EXPECT_NE(std::string(e.what()).find("1 of 2 searches finished; kept " + o.csv + " (incomplete)"), std::string::npos)
        << e.what();
  }
  std::ifstream in(o.csv);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(without_cpu(text).size(), 2u);
}

}  // namespace
}  // namespace clothsim::clip
