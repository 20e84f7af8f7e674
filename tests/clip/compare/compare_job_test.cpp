// compare's plan as a library (clip/compare/compare_job.h): each lane one CompareLane whose
// spec, folder, model, label and name belong together, through --vary and --shard.
#include "clip/compare/compare_job.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "clip/common/cli_common.h"
#include "cli/usage_error.h"
#include "test_support.h"

using namespace clothsim;
using namespace clothsim::clip;

namespace {

// A small drape, two integrators by two stiffnesses, written to a summary only: no pictures.
CompareRequest small_grid(const std::string& out) {
  CompareRequest o;
  o.scene.path = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";
  o.scene.sets = {"cloth.particles=[5,5]"};
  o.scene.duration = 0.1;
  o.integrators = "symplectic_euler,rk4";
  o.integrators_given = true;
  o.vary = "ks=2e3,2e4";
  o.summary = out + "/summary.json";
  o.frames_dir.clear();
  return o;
}

}  // namespace

TEST(PlanCompare, AVaryGridIsOneLanePerIntegratorAndValueEachWithItsOwnModelAndNames) {
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job";
  std::filesystem::create_directories(out);
  ComparePlan p = plan_compare(small_grid(out));
  ASSERT_EQ(p.lanes.size(), 4u);  // rows by integrator, a column per value
  ASSERT_EQ(p.vary_models.size(), 2u);
  for (std::size_t i = 0; i < p.lanes.size(); ++i) {
    const CompareLane& l = p.lanes[i];
    EXPECT_EQ(l.spec.kind, i < 2 ? IntegratorKind::SymplecticEuler : IntegratorKind::Rk4);
    EXPECT_EQ(l.model, &p.vary_models[i % 2]) << "lane " << i << " runs its value's model";
    EXPECT_EQ(l.label, l.spec.name() + "  " + l.value);
    EXPECT_EQ(l.name, l.spec.name() + ", " + l.value);
    EXPECT_FALSE(l.step_choice.empty());
    EXPECT_EQ(l.dir.find(' '), std::string::npos);
  }
  EXPECT_NE(p.lanes[0].value, p.lanes[1].value);
  EXPECT_EQ(p.lanes[0].value, p.lanes[2].value);
  // The stiffer value's springs are stiffer in its model, and only there.
  const auto stiffest = [](const Model* m) { return *std::max_element(m->springs.ks.begin(), m->springs.ks.end()); };
  EXPECT_GT(stiffest(p.lanes[1].model), stiffest(p.lanes[0].model));
  // The lists the pipeline and the summary take are the lanes' fields, in lane order.
  const SummaryContext c = p.summary_context();
  ASSERT_EQ(c.names.size(), 4u);
  EXPECT_EQ(c.names[3], p.lanes[3].name);
  EXPECT_EQ(p.models()[1], p.lanes[1].model);
  EXPECT_EQ(p.labels()[2], p.lanes[2].label);
}

TEST(PlanCompare, WithoutVaryEveryLaneRunsThePlansModelUnderItsOwnName) {
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  o.vary.clear();
  o.match = {"none"};
  ComparePlan p = plan_compare(o);
  ASSERT_EQ(p.lanes.size(), 2u);
  EXPECT_TRUE(p.models().empty());
  EXPECT_TRUE(p.labels().empty());
  EXPECT_EQ(p.lanes[0].dir, "symplectic_euler");
  EXPECT_EQ(p.lanes[1].dir, "rk4");
  EXPECT_EQ(p.lanes[1].name, "rk4");
}

TEST(KeepShardLanes, APartKeepsWholeLanes) {
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_shard";
  std::filesystem::remove_all(out);
  CompareRequest o = small_grid(out);
  o.summary.clear();
  o.frames_dir = out + "/frames";
  o.shard = "2/2";
  o.look.color_range = "1e-4,1e-1";  // a part's colour scale is given, not chosen from its lanes
  ComparePlan p = plan_compare(o);
  const std::vector<CompareLane> all = p.lanes;
  keep_shard_lanes(o, p);
  ASSERT_FALSE(p.lanes.empty());
  ASSERT_LT(p.lanes.size(), all.size());
  for (const CompareLane& kept : p.lanes) {  // each kept lane is one of the plan's, whole
    bool found = false;
    for (const CompareLane& l : all)
      found = found || (l.dir == kept.dir && l.model == kept.model && l.label == kept.label && l.name == kept.name &&
                        l.step_choice == kept.step_choice && l.spec.spelling() == kept.spec.spelling());
    EXPECT_TRUE(found) << kept.dir;
  }
}

TEST(PlanComparePart, RunsAPartsLanesRefusesOutputsAPartCannotWriteAndSaysWhenItHasNone) {
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_part";
  std::filesystem::remove_all(out);
  CompareRequest o = small_grid(out);
  o.summary.clear();
  o.frames_dir = out + "/frames";
  o.look.color_range = "1e-4,1e-1";
  o.shard = "1/2";
  std::optional<ComparePlan> part = plan_compare_part(o);
  ASSERT_TRUE(part);
  EXPECT_LT(part->lanes.size(), 4u) << "part 1 of 2 runs some of the four lanes";
  o.shard = "5/5";  // more parts than lanes: the last one has none to run
  EXPECT_FALSE(plan_compare_part(o));
  o.shard = "1/2";
  o.summary = out + "/summary.json";  // a part writes its frames only: merge-free outputs are refused
  EXPECT_THROW(plan_compare_part(o), UsageError);
}

TEST(PlanCompare, AVaryGridOfAFixedPointSceneNamesItsRowsByTheMethodThatRuns) {
  // Without --integrators the row is the scene's integrator; a scene whose implicit_euler is
  // the course's fixed point runs the fixed point, and its rows say so (they said implicit_euler).
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_fixed_point";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  o.scene.sets.insert(o.scene.sets.end(), {"integrator=implicit_euler", "implicit.solver=fixed_point", "dt=1e-4"});
  o.integrators = default_comparison_list();  // as the command sets it when not given
  o.integrators_given = false;
  ComparePlan p = plan_compare(o);
  ASSERT_EQ(p.lanes.size(), 2u);
  for (const CompareLane& l : p.lanes) {
    EXPECT_TRUE(l.spec.fixed_point);
    EXPECT_EQ(l.spec.stepless_spelling(), std::string(kFixedPointName));
    EXPECT_EQ(l.name.rfind(l.spec.name(), 0), 0u) << l.name;
    EXPECT_NE(l.name.find("fixed point"), std::string::npos) << l.name;
    EXPECT_EQ(l.model->implicit.solver, ImplicitSolver::FixedPoint) << "what it runs is the fixed point";
  }
}

TEST(PlanCompare, APlanStartsNoThreadAndMovesAsAValue) {
  // The drape (projected contacts: a fixed-step reference) coloured by error: planning starts no
  // reference (run_compare does), so a plan moved, or run twice, gives the same errors as a plan
  // never moved. The cache is off: each run computes its reference.
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_moved";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  o.vary.clear();
  o.summary.clear();
  o.integrators = "symplectic_euler,midpoint";
  o.look.color = "error";
  o.look.no_reference_cache = true;
  o.table_wanted = true;
  ComparePlan planned = plan_compare(o);
  const Model* model = planned.model.get();
  const ComparePlan moved = std::move(planned);
  EXPECT_EQ(moved.model.get(), model) << "the model stays where the lanes read it";
  const PipelineReport a = run_compare(o, moved);
  const PipelineReport b = run_compare(o, moved);
  const PipelineReport c = run_compare(o, plan_compare(o));
  ASSERT_EQ(a.lanes.size(), 2u);
  ASSERT_EQ(a.references.size(), 1u);
  EXPECT_EQ(a.references[0].result.cache, "off");
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(a.lanes[i].field_max, b.lanes[i].field_max) << i;
    EXPECT_EQ(a.lanes[i].field_max, c.lanes[i].field_max) << i;
    EXPECT_EQ(a.lanes[i].result.t, c.lanes[i].result.t) << i;
  }
}

TEST(RunCompare, FrameRowsAreEveryLaneAtEveryClipFrameWithTheErrorTheReportEndsOn) {
  // A front end's rows (Python's compare frames): no clip written, yet a row per lane per frame
  // and at the end between two frames, the last one's error the report's field_last, the
  // largest its field_max.
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_rows";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  o.scene.duration = 0.11;
  o.vary.clear();
  o.summary.clear();
  o.look.color = "error";
  o.look.no_reference_cache = true;
  o.table_wanted = true;
  o.frame_rows_wanted = true;
  const ComparePlan p = plan_compare(o);
  std::vector<LaneFrameRow> rows;
  const PipelineReport report = run_compare(o, p, &rows);
  const long frames = p.targets->frames();
  ASSERT_EQ(frames, static_cast<long>(0.11 * p.scene.render.fps) + 1);
  ASSERT_LT((frames - 1) / p.scene.render.fps, 0.11);
  ASSERT_EQ(rows.size(), 2u * static_cast<std::size_t>(frames + 1));
  for (std::size_t i = 0; i < 2; ++i) {
    double largest = 0.0;
    for (const LaneFrameRow& r : rows)
      if (r.lane == i) largest = std::max(largest, r.field);
    const LaneFrameRow& last = rows[rows.size() - 2 + i];
    EXPECT_EQ(last.lane, i);
    EXPECT_EQ(last.frame_t, 0.11);
    EXPECT_EQ(report.lanes[i].result.t, 0.11) << "the lanes end at the end, not at the last frame";
    EXPECT_EQ(last.field, report.lanes[i].field_last) << i;
    EXPECT_EQ(largest, report.lanes[i].field_max) << i;
    EXPECT_EQ(rows[i].metrics.t, 0.0);
    EXPECT_EQ(rows[i].field, 0.0) << "every lane starts on the reference's state";
  }
  EXPECT_EQ(rows[0].metrics.energies.total(), rows[1].metrics.energies.total());
}

TEST(PlanCompare, CloseVaryValuesMakeLanesOfTheirOwnNamesAndFolders) {
  // --vary ks=100,100.0001 --frames fr made two lanes "ks = 100" writing one folder.
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_close";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  o.vary = "ks=100,100.0001";
  const ComparePlan p = plan_compare(o);
  ASSERT_EQ(p.lanes.size(), 4u);
  for (std::size_t i = 0; i < p.lanes.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_NE(p.lanes[i].dir, p.lanes[j].dir);
      EXPECT_NE(p.lanes[i].label, p.lanes[j].label);
    }
  EXPECT_EQ(p.lanes[1].value, "ks = 100.0001");
  EXPECT_EQ(p.lanes[1].dir, "symplectic_euler_ks=100.0001");
}

TEST(PlanCompare, RefusesToVaryWhatEveryLaneOfOneClipShares) {
  // The lanes run to the base scene's duration and are drawn at its size: a varied duration
  // or render key would be a label with nothing behind it.
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_shared";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  for (const char* vary : {"duration=0.05,0.1", "render.width=320,640", "render.fps=30,60"}) {
    o.vary = vary;
    const std::string m = clothsim::testing::usage_error([&] { plan_compare(o); });
    EXPECT_EQ(m.rfind("--vary " + std::string(vary).substr(0, std::string(vary).find('=')) + ": every lane", 0), 0u)
        << m;
  }
}

// A lane's own settings ride in its run: the fixed-point lane (and a lane with `:N`) costs a
// run as backward Euler's does, and no Model of its own (the course's lane once copied it).
TEST(PlanCompare, MaxMemoryCountsNoModelForALanesOwnSettings) {
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_lane_memory";
  std::filesystem::create_directories(out);
  CompareRequest o = small_grid(out);
  o.vary.clear();
  o.scene.sets = {"cloth.particles=[256,256]"};
  o.integrators = "implicit_euler,implicit_euler_fixed_point,implicit_euler:3";
  o.scene.max_memory = 1024.0 * 1024;  // refused, every part said
  const std::string m = clothsim::testing::usage_error([&] { plan_compare(o); });
  const auto part = [&](const std::string& name) {  // "NAME 12.3 MB" in the list of parts
    const std::size_t at = m.find(" " + name + " ");
    if (at == std::string::npos) return std::string("(none)");
    const std::size_t from = at + name.size() + 2;
    return m.substr(from, m.find_first_of(",)", from) - from);
  };
  EXPECT_NE(part("implicit_euler@0.0001"), "(none)") << m;
  EXPECT_EQ(part("implicit_euler_fixed_point@0.0001"), part("implicit_euler@0.0001")) << m;
  EXPECT_EQ(part("implicit_euler@0.0001:3"), part("implicit_euler@0.0001")) << m;
}

TEST(PlanCompare, MaxMemoryCountsEachLanesExportAndARefusalMakesNoFolder) {
  const std::string out = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/compare_job_export_memory";
  std::filesystem::remove_all(out);
  CompareRequest o = small_grid(out);
  o.vary.clear();
  o.summary.clear();
  o.scene.sets = {"cloth.particles=[256,256]"};
  o.export_path = out + "/x.pvd";
  o.scene.max_memory = 150.0 * 1024 * 1024;  // the lanes alone fit, not with two exports of 37.5 MB
  const std::string m = clothsim::testing::usage_error([&] { plan_compare(o); });
  EXPECT_NE(m.find("export of 2 lanes 75 MB"), std::string::npos) << m;
  EXPECT_FALSE(std::filesystem::exists(out)) << "refused before its folders are made";
  o.export_path.clear();
  o.summary = out + "/s.json";
  std::filesystem::create_directories(out);
  EXPECT_NO_THROW(plan_compare(o));
}
