// RunWorker: one run on its own thread, handing over a snapshot per target in order, and
// freezing on its last good frame when it diverges.
#include "compare_runner.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

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

}  // namespace

TEST(RunWorker, HandsOverOneSnapshotPerTargetInOrderSizedToTheTile) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(5, 20.0);
  RunWorker worker(model, IntegratorKind::SymplecticEuler, 1e-3, targets, 160, 90);
  TileSnapshot snap;
  for (int k = 0; k < 5; ++k) {
    ASSERT_TRUE(worker.next(snap)) << k;
    EXPECT_FALSE(snap.frozen);
    EXPECT_EQ(snap.frame.width, 160);
    EXPECT_EQ(snap.frame.height, 90);
    char t[32];
    std::snprintf(t, sizeof t, "t = %.3f s", k / 20.0);
    bool has_time = false;
    for (const auto& line : snap.frame.overlay_lines) has_time = has_time || line == t;
    EXPECT_TRUE(has_time) << "overlay shows " << t;
    EXPECT_NE(snap.frame.overlay_lines.back().find("force evals"), std::string::npos);
  }
  EXPECT_FALSE(worker.next(snap)) << "no more after the last target";
  worker.join();
  const RunSummary s = worker.summary();
  EXPECT_EQ(s.totals.steps, 200);  // 0.2 s at 1 ms
  EXPECT_EQ(s.totals.force_evals, 200);
  EXPECT_DOUBLE_EQ(s.t, 0.2);
  EXPECT_FALSE(s.divergence);
}

TEST(RunWorker, FreezesOnTheLastGoodFrameWithABannerWhenTheRunDiverges) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(30, 20.0);
  RunWorker worker(model, IntegratorKind::ExplicitEuler, 1e-2, targets, 160, 90);
  TileSnapshot snap, previous;
  int handed = 0;
  while (worker.next(snap)) {
    ++handed;
    if (snap.frozen) break;
    previous = snap;
  }
  ASSERT_TRUE(snap.frozen) << "explicit Euler at w h > 1 with heavy damping diverges";
  EXPECT_GE(handed, 2) << "t = 0 is always good";
  EXPECT_LT(handed, 30);
  EXPECT_FALSE(worker.next(snap)) << "nothing after the frozen frame";
  EXPECT_EQ(snap.frame.banner.rfind("DIVERGED at t = ", 0), 0u) << snap.frame.banner;
  EXPECT_EQ(snap.frame.cloth_positions, previous.frame.cloth_positions)
      << "the frozen picture is the last good state";
  EXPECT_EQ(snap.frame.overlay_lines.back().rfind("diverged: ", 0), 0u);
  worker.join();
  EXPECT_TRUE(worker.summary().divergence.has_value());
}

TEST(RunWorker, StopsWhenAskedEvenWithAFullQueue) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(1000, 20.0);  // 50 s of sheet: far more than the test waits for
  RunWorker worker(model, IntegratorKind::SymplecticEuler, 1e-3, targets, 32, 32, 2);
  TileSnapshot snap;
  ASSERT_TRUE(worker.next(snap));
  worker.stop();
  worker.join();  // returns: the thread saw the stop while blocked on the full queue
  EXPECT_LT(worker.summary().totals.steps, 1000 * 50);
}

TEST(RunWorker, AnInterruptStopsTheRunMidTargetAndFreesTheCallerOfNext) {
  // One target 1e9 steps away: without a check inside the stepping loop this would run for
  // minutes; the interrupt is seen before the next step and next() returns without a snapshot.
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const TargetPlan far(1000.0, 1.0, false, {});  // a single target at t = 1000 s
  std::atomic<bool> signal{false};
  RunWorker worker(model, IntegratorKind::SymplecticEuler, 1e-6, far, 32, 32, 4, [&] { return signal.load(); });
  std::thread raiser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    signal = true;
  });
  TileSnapshot snap;
  EXPECT_FALSE(worker.next(snap));
  raiser.join();
  worker.join();
  const RunSummary s = worker.summary();
  EXPECT_GT(s.totals.steps, 0);
  EXPECT_LT(s.totals.steps, 1'000'000'000);
}

TEST(RunWorker, SaysNotConvergedWithTheStepsMissedSoFar) {
  // One Newton iteration cannot meet 1e-12 on a sagging sheet: steps miss it as they come,
  // and each snapshot counts the misses up to its own time, not the run's final total.
  const Model model = clothsim::testing::model_from_yaml(
      std::string(kSheet) + "implicit: {newton_max_iterations: 1, newton_tolerance: 1.0e-12}\n");
  const auto targets = frames(4, 20.0);
  RunWorker worker(model, IntegratorKind::ImplicitEuler, 1e-3, targets, 32, 32);
  TileSnapshot snap;
  ASSERT_TRUE(worker.next(snap));
  EXPECT_EQ(snap.frame.banner, "") << "no step taken at t = 0";
  long previous = 0;
  for (int k = 1; k < 4; ++k) {
    ASSERT_TRUE(worker.next(snap));
    long missed = 0;
    ASSERT_EQ(std::sscanf(snap.frame.banner.c_str(), "NOT CONVERGED (%ld steps)", &missed), 1)
        << snap.frame.banner;
    EXPECT_GT(missed, previous) << "at t = " << k / 20.0;
    EXPECT_LE(missed, 50L * k) << "no more than the steps taken so far";
    previous = missed;
  }
  worker.join();
  EXPECT_EQ(worker.summary().totals.unconverged_steps, previous);
}
