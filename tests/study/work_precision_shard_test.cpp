// A sharded study's parts join into the single-process result: bench points measured
// against a saved reference, and stability searches run in parts, equal the whole study's.
#include "study/work_precision_shard.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"
#include "study/shard.h"
#include "study/stability.h"

namespace clothsim::analysis {
namespace {

using testing::scene_path;

Model chain() { return build_model(load_scene(scene_path("chain.yaml"), {})); }

WorkPrecisionSpec chain_spec() {
  WorkPrecisionSpec spec;
  spec.integrators = {IntegratorKind::SymplecticEuler, IntegratorKind::Rk4, IntegratorKind::ExplicitEuler};
  spec.dts = {2e-4, 4e-4, 8e-4};
  spec.duration = 0.04;
  spec.jobs = 2;
  return spec;
}

TEST(WorkPrecisionShard, PartsMeasuredAgainstASavedReferenceEqualTheWholeStudy) {
  const Model model = chain();
  const WorkPrecisionSpec spec = checked(chain_spec());
  const WorkPrecisionResult whole = work_precision(model, spec);
  const ShardReference ref = read_reference(reference_text(run_reference(model, spec, {}), model.num_particles));
  EXPECT_TRUE(ref.finished);
  EXPECT_EQ(ref.dt, whole.reference.dt);
  EXPECT_EQ(ref.change_rms_over_time, whole.reference.change_rms);  // the study judges over time
  EXPECT_EQ(ref.samples.size(), static_cast<std::size_t>(whole.reference.samples));
  std::vector<WorkPrecisionPoint> joined(whole.points.size());
  for (int k = 1; k <= 2; ++k) {
    std::vector<double> costs;
    for (const WorkPrecisionPoint& p : planned_points(spec)) costs.push_back(cost_estimate(p.integrator, spec.duration, p.dt));
    run_points(model, spec, ref, shard_items(costs, {k, 2}), {},
               [&](std::size_t item, const WorkPrecisionPoint& p) { joined[item] = p; });
  }
  for (std::size_t i = 0; i < whole.points.size(); ++i) {
    EXPECT_EQ(joined[i].integrator, whole.points[i].integrator);
    EXPECT_EQ(joined[i].dt, whole.points[i].dt);
    EXPECT_EQ(joined[i].steps, whole.points[i].steps);
    EXPECT_EQ(joined[i].diverged, whole.points[i].diverged);
    if (whole.points[i].finished) {
      EXPECT_EQ(joined[i].rms_error, whole.points[i].rms_error) << i;
    }
  }
}

TEST(WorkPrecisionShard, RefusesASavedReferenceCutShort) {
  EXPECT_THROW(read_reference("1 1 0x1p-10 0x0p+0 0x0p+0 3\n0x1p+0 0x0p+0 0x0p+0 0x1p+0\n"), StudyError);
  EXPECT_THROW(read_reference("garbage"), StudyError);
}

TEST(StabilityShard, SearchesRunInPartsEqualTheWholeSweep) {
  const Model soft = chain();
  const Model stiff = build_model(load_scene(scene_path("chain.yaml"), {"cloth.springs.structural.stiffness=1e6"}));
  StabilitySpec spec;
  spec.integrators = {IntegratorKind::SymplecticEuler, IntegratorKind::Midpoint};
  spec.duration = 0.05;
  spec.min_dt = 1e-6;
  spec.max_dt = 1e-3;
  spec.jobs = 2;
  const std::vector<StabilityCase> cases{{1.0, &soft}, {2.0, &stiff}};
  const std::vector<StabilityLimit> whole = stability_sweep(cases, spec);
  std::vector<StabilityLimit> joined(whole.size());
  for (std::size_t item : std::vector<std::size_t>{3, 0})  // out of order, as parts finish
    stability_sweep_items(cases, spec, {item}, {}, [&](std::size_t i, const StabilityLimit& l) { joined[i] = l; });
  for (std::size_t item : std::vector<std::size_t>{1, 2})
    stability_sweep_items(cases, spec, {item}, {}, [&](std::size_t i, const StabilityLimit& l) { joined[i] = l; });
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(joined[i].value, whole[i].value);
    EXPECT_EQ(joined[i].integrator, whole[i].integrator);
    EXPECT_EQ(joined[i].stable_dt, whole[i].stable_dt) << i;
    EXPECT_EQ(joined[i].trials, whole[i].trials);
  }
  EXPECT_GT(search_cost(stiff, IntegratorKind::Midpoint, spec), search_cost(soft, IntegratorKind::Midpoint, spec));
}

}  // namespace
}  // namespace clothsim::analysis
