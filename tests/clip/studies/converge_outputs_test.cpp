// converge's files (src/clip/studies/converge_outputs.h), written the same by the CLI and the
// Python module: the summary's means over the states, and a shard's rows as the whole study's.
#include "clip/studies/converge_outputs.h"

#include <gtest/gtest.h>

#include <fstream>

#include "cli/cli_process.h"
#include "clip/studies/csv_rows.h"
#include "clip/merge/study_merge.h"
#include "clip/studies/study_shard.h"
#include "core/integrators/integrator_kind.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "test_support.h"

namespace clothsim::clip {
namespace {

using testing::scratch_dir;

ConvergencePoint point(const char* method, int state, int iterations, double rms, const char* wrong = "") {
  ConvergencePoint p;
  p.method = *parse_integrator(method);
  p.state = state, p.iterations = iterations, p.rms = rms, p.cpu_seconds = 1e-3 * iterations, p.wrong = wrong;
  return p;
}

TEST(ConvergeMeans, AveragesEachMethodAndIterationCountOverTheStatesAndCountsTheWrongOnes) {
  const auto means = converge_means({point("vbd", 0, 1, 1e-2), point("vbd", 1, 1, 3e-2, "energy gained"),
                                     point("vbd", 0, 2, 1e-3), point("vbd", 1, 2, 3e-3)});
  const int vbd = static_cast<int>(*parse_integrator("vbd"));
  ASSERT_EQ(means.size(), 2u);
  EXPECT_DOUBLE_EQ(means.at({vbd, 1}).rms, 2e-2);
  EXPECT_EQ(means.at({vbd, 1}).wrong, 1);
  EXPECT_EQ(means.at({vbd, 2}).n, 2);
  EXPECT_DOUBLE_EQ(means.at({vbd, 2}).cpu, 2e-3);
}

// The rows without their cpu_seconds (measured, never equal).
std::vector<std::vector<std::string>> without_cpu(const std::string& text) {
  return testing::csv_rows_without(text, {"cpu_seconds"});
}

TEST(ConvergeShard, JournalsTheWholeStudysRowsAndWritesTheSummaryOnlyThroughMerge) {
  ConvergeOptions o;
  o.scene.path = testing::scene_path("drape.yaml");
  o.integrators = "vbd,xpbd";
  o.states = "2";
  o.max_iterations = "3";
  const SceneDef scene = load_scene(o.scene.path, {"cloth.particles=[5,5]"});
  const Model model = build_model(scene);
  const ConvergenceSpec spec = plan_converge(o);
  const std::vector<ConvergencePoint> whole = convergence_study(model, spec, {});
  ASSERT_EQ(whole.size(), 2u * 2 * 3);
  const std::string text = written_text([&](std::FILE* f) { write_converge_csv(f, model.name, whole); });

  o.csv = scratch_dir("converge_outputs_shard") + "/cv.csv";
  o.shard = "1/1";
  EXPECT_EQ(converge_shard(o, model, spec, {}), 0);
  EXPECT_EQ(without_cpu(merged_csv({read_part(shard_dir(o.csv, {1, 1}))})), without_cpu(text));
  o.summary = o.csv + ".json";
  EXPECT_THROW(converge_shard(o, model, spec, {}), UsageError) << "a shard writes no summary: merge does";
}

TEST(WriteConvergeOutputs, WritesTheCsvAndAMeanPerMethodAndIterationCount) {
  ConvergeOptions o;
  const std::string dir = scratch_dir("converge_outputs_files");
  o.csv = dir + "/cv.csv", o.summary = dir + "/cv.json";
  const Model model = testing::model_from_yaml(testing::kCornerSheet);
  ConvergenceSpec spec;
  spec.h = 1.0 / 60, spec.states = 2, spec.max_iterations = 2;
  write_converge_outputs(o, "inline.yaml", model, spec,
                         {point("xpbd", 0, 1, 1e-2), point("xpbd", 1, 1, 3e-2), point("xpbd", 0, 2, 1e-3),
                          point("xpbd", 1, 2, 3e-3)},
                         nullptr);
  std::ifstream csv(o.csv), json(o.summary);
  const std::string rows((std::istreambuf_iterator<char>(csv)), {}), summary((std::istreambuf_iterator<char>(json)), {});
  EXPECT_EQ(without_cpu(rows).size(), 1u + 4);
  EXPECT_NE(summary.find("\"mean_rms_distance\": 0.02"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"max_iterations\": 2"), std::string::npos) << summary;
}

}  // namespace
}  // namespace clothsim::clip
