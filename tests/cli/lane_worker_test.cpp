// LaneWorker: one lane on its own thread, handing over a frame per target in order, and
// freezing on its last finite state when it diverges.
#include "lane_worker.h"

#include <gtest/gtest.h>

#include "test_support.h"

using namespace clothsim;
using namespace clothsim::cli;

namespace {

// A 4 x 4 sheet pinned at its corners, lightly damped: stable for symplectic Euler at 1 ms
// (w h ~ 0.3), while explicit Euler at 10 ms (w h > 1.4, growth |1 + i w h| per step) blows up.
const char* kSheet = R"(
name: sheet
dt: 1.0e-3
cloth: {particles: [4, 4], size: [1, 1], pinned: corners,
        springs: {structural: {stiffness: 20000, damping: 5}}}
)";

// n clip frames at fps: t = 0 .. (n - 1) / fps.
TargetPlan frames(int n, double fps) { return TargetPlan((n - 1) / fps, fps, true, {}); }

LaneNeeds picture_and_metrics() {
  LaneNeeds n;
  n.picture = true;
  n.metrics = true;
  return n;
}

}  // namespace

TEST(LaneWorker, HandsOverOneFramePerTargetInOrder) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(5, 20.0);
  LaneWorker worker(model, LaneSpec{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"}, targets, picture_and_metrics());
  LaneFrame f;
  for (int k = 0; k < 5; ++k) {
    ASSERT_TRUE(worker.next(f)) << k;
    EXPECT_FALSE(f.frozen);
    EXPECT_NEAR(f.t, k / 20.0, 1e-12);
    EXPECT_EQ(f.step, 50 * k);
    EXPECT_EQ(f.metrics.step, 50 * k);
    EXPECT_EQ(f.frame.cloth_positions.size(), 3u * 16);
    EXPECT_EQ(f.totals.force_evals, 50 * k);
    EXPECT_TRUE(f.x.empty()) << "positions only when the error field needs them";
  }
  EXPECT_FALSE(worker.next(f)) << "no more after the last target";
  worker.join();
  const LaneResult r = worker.result();
  EXPECT_EQ(r.totals.steps, 200);  // 0.2 s at 1 ms
  EXPECT_DOUBLE_EQ(r.t, 0.2);
  EXPECT_FALSE(r.divergence);
}

TEST(LaneWorker, ComputesOnlyWhatIsNeeded) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(2, 20.0);
  LaneNeeds needs;
  needs.positions = true;
  needs.field = FieldKind::Strain;
  LaneWorker worker(model, LaneSpec{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"}, targets, needs);
  LaneFrame f;
  ASSERT_TRUE(worker.next(f));
  ASSERT_TRUE(worker.next(f));
  EXPECT_TRUE(f.frame.cloth_positions.empty()) << "no picture asked for";
  EXPECT_EQ(f.x.size(), 3u * 16);
  ASSERT_EQ(f.field.size(), 16u);
  for (float s : f.field) EXPECT_GE(s, 0.f);
}

TEST(LaneWorker, FreezesOnTheLastFiniteStateAtTheStepItDiverged) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(30, 20.0);
  LaneWorker worker(model, LaneSpec{IntegratorKind::ExplicitEuler, 1e-2, "1e-2"}, targets, picture_and_metrics());
  LaneFrame f, previous;
  int handed = 0;
  while (worker.next(f)) {
    ++handed;
    if (f.frozen) break;
    previous = f;
  }
  ASSERT_TRUE(f.frozen) << "explicit Euler at w h > 1 with heavy damping diverges";
  EXPECT_GE(handed, 2) << "t = 0 is always good";
  EXPECT_LT(handed, 30);
  EXPECT_FALSE(worker.next(f)) << "nothing after the frozen frame";
  ASSERT_TRUE(f.divergence);
  EXPECT_EQ(f.t, f.divergence->t) << "the frozen frame is at the divergence's time";
  EXPECT_GT(f.step, previous.step) << "not the last output frame: the state where it broke";
  EXPECT_LE(f.step, f.divergence->step);
  for (float v : f.frame.cloth_positions) ASSERT_TRUE(std::isfinite(v)) << "the last finite state";
  // The same lane as a Run: the same divergence.
  clothsim::Run run(model, IntegratorKind::ExplicitEuler, 1e-2);
  run.advance_to(2.0);
  ASSERT_TRUE(run.divergence());
  EXPECT_EQ(run.divergence()->step, f.divergence->step);
  EXPECT_EQ(run.divergence()->t, f.divergence->t);
  worker.join();
  EXPECT_TRUE(worker.result().divergence.has_value());
}
