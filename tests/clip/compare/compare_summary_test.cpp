// compare's verdicts in numbers (clip/compare/compare_summary.h): unresolved against diverged.
#include "clip/compare/compare_summary.h"

#include <gtest/gtest.h>

using namespace clothsim;
using namespace clothsim::clip;

namespace {

// Two lanes measured at one frame against one reference, both under 10x its error; the
// second diverged after that frame.
PipelineReport two_lanes_under_the_reference() {
  PipelineReport report;
  report.references.emplace_back();
  report.references[0].result.estimated_error = 1e-6;
  for (int i = 0; i < 2; ++i) {
    LaneReport lane;
    lane.reference = 0;
    lane.field_count = 1;
    lane.field_max = lane.field_last = 2e-7;
    report.lanes.push_back(lane);
  }
  report.lanes[1].result.divergence = Divergence{53, 0.0212, "kinetic energy 2.45e+09 J exceeds the bound"};
  return report;
}

}  // namespace

TEST(LaneUnresolved, IsALaneTheReferenceCannotTellAndNeverOneThatDiverged) {
  // On --integrators course a diverged lane read "unresolved (measured at 1 frame ...)".
  const PipelineReport report = two_lanes_under_the_reference();
  EXPECT_TRUE(lane_unresolved(report, 0, FieldKind::Error));
  EXPECT_FALSE(lane_unresolved(report, 1, FieldKind::Error)) << "diverged, not unresolved";
  EXPECT_FALSE(lane_unresolved(report, 0, FieldKind::Strain)) << "only an error is judged against a reference";
}
