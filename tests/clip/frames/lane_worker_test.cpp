// LaneWorker: one lane on its own thread, handing over a frame per target in order, and
// freezing on its last finite state when it diverges.
#include "clip/frames/lane_worker.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include "test_support.h"
#include "view/snapshot.h"

using namespace clothsim;
using namespace clothsim::clip;

namespace {

using clothsim::testing::kCornerSheet;
const char* const kSheet = kCornerSheet;  // (test_support.h)

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
  LaneWorker worker(model, Lane{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"}, targets, picture_and_metrics());
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
  LaneWorker worker(model, Lane{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"}, targets, needs);
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
  LaneWorker worker(model, Lane{IntegratorKind::ExplicitEuler, 1e-2, "1e-2"}, targets, picture_and_metrics());
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

TEST(LaneWorker, ATileLaneFreezesOnTheLastTargetsStateOrTheStartBeforeAny) {
  // LaneNeeds::hold_sane: the frozen frame shows the state handed over last, not the blow-up.
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  LaneNeeds needs = picture_and_metrics();
  needs.hold_sane = true;
  const auto targets = frames(30, 20.0);
  LaneWorker worker(model, Lane{IntegratorKind::ExplicitEuler, 1e-2, "1e-2"}, targets, needs);
  LaneFrame f, previous;
  while (worker.next(f) && !f.frozen) previous = f;
  ASSERT_TRUE(f.frozen && f.divergence);
  EXPECT_EQ(f.t, f.divergence->t) << "the frame's time is still the divergence's";
  EXPECT_EQ(f.step, previous.step) << "the state shown is the last target's";
  EXPECT_EQ(f.shown_t, previous.t);
  EXPECT_EQ(f.frame.cloth_positions, previous.frame.cloth_positions);
  EXPECT_GT(f.metrics.step, previous.step) << "the metrics are the state it stopped in, as run --metrics'";
  // A still after the divergence, the lane's only target: the start is its last sane state.
  const TargetPlan late(0.5, 20.0, false, {0.5});
  LaneWorker alone(model, Lane{IntegratorKind::ExplicitEuler, 1e-2, "1e-2"}, late, needs);
  ASSERT_TRUE(alone.next(f));
  ASSERT_TRUE(f.frozen);
  EXPECT_EQ(f.step, 0);
  EXPECT_EQ(f.shown_t, 0.0);
  EXPECT_EQ(f.frame.cloth_positions, make_render_frame(model, initial_state(model), {}).cloth_positions);
}

namespace {

LaneNeeds standing_for(std::vector<double> steps) {
  LaneNeeds n;
  n.stand_for = std::move(steps);
  return n;
}

}  // namespace

TEST(LaneWorker, TheReferenceRunsAsFarAsALiveLaneOfALargeStepStands) {
  // A lane of 2 s on a 0.5 s clip stands at 2 s from the second frame on, and is measured
  // there: the reference goes to 2 s (the clip's end plus the largest live step bounds it).
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(16, 30.0);
  LaneWorker reference(model, Lane{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"}, targets, standing_for({2.0, 1e-2}));
  LaneFrame f;
  int handed = 0;
  while (reference.next(f)) {
    ASSERT_EQ(f.x_for.size(), 2u);
    EXPECT_TRUE(f.x_for[0] && f.x_for[1]) << "target " << handed;
    ++handed;
  }
  EXPECT_EQ(handed, 16);
  reference.join();
  EXPECT_NEAR(reference.result().t, 2.0, 1e-9);
}

// The reference lane standing in for lanes of `steps` over 16 frames at 30 Hz (0.5 s), at 1 ms,
// lane `lane` dropped (diverged) from within the reference's thread just before its step
// `drop_at` (counted by the stop check it polls before every step): what a pipeline does when
// the lane's frozen frame comes, at a step of the reference the test chooses.
struct DroppedReference {
  std::vector<LaneFrame> frames;
  LaneResult result;
};
DroppedReference reference_dropping(const Model& model, std::vector<double> steps, std::size_t lane, long drop_at) {
  const auto targets = frames(16, 30.0);
  const std::thread::id consumer = std::this_thread::get_id();
  std::atomic<long> polls{0};
  LaneWorker* self = nullptr;
  std::atomic<bool> constructed{false};
  const auto poll = [&] {
    // (next() polls too, from the consumer's thread: only the reference's steps count)
    if (std::this_thread::get_id() != consumer && ++polls == drop_at) {
      while (!constructed) std::this_thread::yield();
      self->drop_lane(lane);
    }
    return false;
  };
  LaneWorker reference(model, Lane{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"}, targets,
                       standing_for(std::move(steps)), kLaneQueueCapacity, poll);
  self = &reference;
  constructed = true;
  DroppedReference out;
  for (LaneFrame f; reference.next(f);) out.frames.push_back(f);
  reference.join();
  out.result = reference.result();
  return out;
}

TEST(LaneWorker, TheReferenceStopsWithinAStepOfALaneDroppedInTheMiddleOfAnAdvance) {
  // The lane of 1e4 s diverged on its first step (as rk4@20 does on the drape). The reference
  // served the lane of 0.01 s to the clip's end (500 steps, and its check at twice the step
  // 250: both poll) and is on its way to 1e4 s (1e7 steps) for the other when, at the 1000th
  // poll (its step 750), it is dropped: it stops there, and every target goes out with the
  // live lane's positions.
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const DroppedReference r = reference_dropping(model, {1e4, 1e-2}, 0, 1000);
  ASSERT_EQ(r.frames.size(), 16u) << "every target goes out";
  for (std::size_t k = 0; k < r.frames.size(); ++k) {
    ASSERT_EQ(r.frames[k].x_for.size(), 2u);
    EXPECT_TRUE(r.frames[k].x_for[1]) << "the live lane at target " << k;
    if (k > 0) {
      EXPECT_FALSE(r.frames[k].x_for[0]) << "the dropped lane at target " << k;
    }
  }
  EXPECT_NEAR(r.result.t, 0.75, 1e-3 + 1e-9) << "stopped at the step it was dropped at, not 1e4 s";
  EXPECT_FALSE(r.result.divergence);
}

TEST(LaneWorker, TheReferenceRunsNoFurtherThanTheClipsEndPlusTheLargestLiveStep) {
  // Dropped at its first step: the reference never runs for the lane of 1e4 s, only to the
  // live lane's last landing (0.5 s), plus at most one step of its own.
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const DroppedReference r = reference_dropping(model, {1e4, 1e-2}, 0, 1);
  ASSERT_EQ(r.frames.size(), 16u);
  for (const LaneFrame& f : r.frames) EXPECT_TRUE(f.x_for[1]);
  EXPECT_LE(r.result.t, 0.5 + 1e-3 + 1e-9);
  EXPECT_GE(r.result.t, 0.5 - 1e-9) << "the live lane was served to its last landing";
}

TEST(LaneWorker, TheReferenceStopsRunningWhenEveryLaneHasDiverged) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const DroppedReference r = reference_dropping(model, {1e4}, 0, 1000);
  EXPECT_LE(r.result.t, 1.0 + 1e-9) << "not on to 1e4 s";
  for (std::size_t k = 1; k < r.frames.size(); ++k) EXPECT_FALSE(r.frames[k].x_for[0]);
}

namespace {

// Every frame a reference lane hands over, until the last.
std::vector<LaneFrame> all_frames(LaneWorker& reference) {
  std::vector<LaneFrame> out;
  for (LaneFrame f; reference.next(f);) out.push_back(f);
  reference.join();
  return out;
}

}  // namespace

namespace {

// Whether two runs of a reference handed over the same frames, to the bit.
void expect_same_frames(const std::vector<LaneFrame>& a, const std::vector<LaneFrame>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].t, b[k].t);
    EXPECT_EQ(a[k].reference_error, b[k].reference_error) << "target " << k;
    EXPECT_EQ(a[k].energy, b[k].energy) << "target " << k;
    ASSERT_EQ(a[k].x_for.size(), b[k].x_for.size());
    for (std::size_t lane = 0; lane < a[k].x_for.size(); ++lane) {
      ASSERT_EQ(!a[k].x_for[lane], !b[k].x_for[lane]);
      if (a[k].x_for[lane]) EXPECT_EQ(*a[k].x_for[lane], *b[k].x_for[lane]) << "target " << k << ", lane " << lane;
    }
  }
}

// A cache of its own under the test output folder, emptied.
analysis::ReferenceCacheSettings fresh_cache(const std::string& name) {
  analysis::ReferenceCacheSettings c;
  c.dir = std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/" + name;
  std::filesystem::remove_all(c.dir);
  return c;
}

}  // namespace

TEST(LaneWorker, AReferenceComputedOnceIsServedFromTheCacheFrameForFrame) {
  // The first run computes and stores; the second serves the same frames (positions at every
  // lane's times, estimate, energy samples) and result without stepping; a changed model
  // misses; a damaged entry is recomputed and stored again; with no cache nothing is stored.
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(16, 30.0);
  const Lane spec{IntegratorKind::Rk4, 1e-3, "1e-3"};
  LaneNeeds needs = standing_for({1e-3, 7.5e-3, 0.1});
  needs.energy_every = 1.0 / 60.0;
  needs.cache = fresh_cache("lane_worker_cache");
  LaneWorker first(model, spec, targets, needs);
  const std::vector<LaneFrame> computed = all_frames(first);
  EXPECT_EQ(first.result().cache, "stored");
  LaneWorker second(model, spec, targets, needs);
  expect_same_frames(all_frames(second), computed);
  EXPECT_EQ(second.result().cache, "reused");
  EXPECT_EQ(second.result().cache_file, first.result().cache_file);
  EXPECT_EQ(second.result().totals.steps, first.result().totals.steps);
  EXPECT_EQ(second.result().estimated_error, first.result().estimated_error);
  EXPECT_EQ(second.result().computed_cpu_seconds, first.result().totals.cpu_seconds);

  const Model stiffer = clothsim::testing::model_from_yaml(kSheet, {"cloth.springs.structural.stiffness=30000"});
  LaneWorker other(stiffer, spec, targets, needs);
  all_frames(other);
  EXPECT_EQ(other.result().cache, "stored") << "another model is another reference";

  {  // a byte of the payload flipped: recomputed, the same frames, stored again
    std::fstream entry(first.result().cache_file, std::ios::in | std::ios::out | std::ios::binary);
    entry.seekg(-100, std::ios::end);
    char c = 0;
    entry.read(&c, 1);
    entry.seekp(-100, std::ios::end);
    c = static_cast<char>(c ^ 0x40);
    entry.write(&c, 1);
  }
  LaneWorker damaged(model, spec, targets, needs);
  expect_same_frames(all_frames(damaged), computed);
  EXPECT_EQ(damaged.result().cache, "stored");

  needs.cache = {};
  LaneWorker bypass(model, spec, targets, needs);
  expect_same_frames(all_frames(bypass), computed);
  EXPECT_EQ(bypass.result().cache, "off");
}

TEST(LaneWorker, AReferenceStoppedBeforeItsEndIsNotStored) {
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const auto targets = frames(16, 30.0);
  const Lane spec{IntegratorKind::Rk4, 1e-3, "1e-3"};
  LaneNeeds needs = standing_for({1e-3});
  needs.cache = fresh_cache("lane_worker_cache_stopped");
  LaneWorker stopped(model, spec, targets, needs);
  LaneFrame f;
  ASSERT_TRUE(stopped.next(f));
  stopped.stop();
  stopped.join();
  EXPECT_EQ(stopped.result().cache, "not stored: stopped before its end");
  EXPECT_EQ(analysis::ReferenceCache(needs.cache).contents().entries, 0);
}

TEST(LaneWorker, AnIterativeReferenceIsNotCached) {
  // Its steps read the model's solver settings, which the key leaves out.
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  LaneNeeds needs = standing_for({1e-3});
  needs.cache = fresh_cache("lane_worker_cache_implicit");
  LaneWorker implicit(model, Lane{IntegratorKind::ImplicitEuler, 1e-3, "1e-3"}, frames(4, 30.0), needs);
  all_frames(implicit);
  EXPECT_EQ(implicit.result().cache, "not cached");
}

TEST(LaneWorker, TheReferenceHoldsAboutASecondAheadOnlyWhereItsPositionsAreSmall) {
  // The drape (625 particles, four lanes of four steps): a second of frames at 30 frames/s.
  // 512 x 512 particles: a lane's queue.
  EXPECT_EQ(reference_queue_capacity(625, {1e-4, 2e-4, 4e-4, 1.0 / 252}), 32u);
  EXPECT_EQ(reference_queue_capacity(512 * 512, {20.0, 1e-4}), kLaneQueueCapacity);
  // Lanes of one step share one copy a frame (ReferenceStand): they count once.
  EXPECT_EQ(reference_queue_capacity(100 * 100, {1e-4, 1e-4, 1e-4, 1e-4}),
            reference_queue_capacity(100 * 100, {1e-4}));
  EXPECT_EQ(reference_queue_capacity(200 * 200, {1e-4, 2e-4, 4e-4, 1e-3}), 8u) << "32 MiB of 3.84 MB frames";
}

namespace {

// The (t, energy) samples a worker hands over, per target, until its last frame.
std::vector<std::vector<std::pair<double, double>>> energy_per_target(LaneWorker& worker) {
  std::vector<std::vector<std::pair<double, double>>> out;
  for (LaneFrame f; worker.next(f);) out.push_back(f.energy);
  worker.join();
  return out;
}

}  // namespace

TEST(LaneWorker, TheErrorsReferenceSamplesTheInsetsEnergyAsARunOfItsOwnDoes) {
  // --color error --inset energy ran the reference twice: as the error's (at the lanes' times)
  // and as a lane sampling its energy every frame. One run now does both: per target the same
  // samples, to the bit, as the lane gives, with a clip's frames, or with a sheet's columns and
  // a still only (samples between targets).
  const Model model = clothsim::testing::model_from_yaml(kSheet);
  const Lane spec{IntegratorKind::SymplecticEuler, 1e-3, "1e-3"};
  const double every = 1.0 / 30.0;
  for (const TargetPlan& plan : {TargetPlan(0.5, 30.0, true, {0.21}, 0.37), TargetPlan(0.5, 30.0, false, {0.1, 0.33}, 0.45)}) {
    LaneNeeds lane;
    lane.energy_every = every;
    LaneWorker alone(model, spec, plan, lane);
    const auto expected = energy_per_target(alone);
    LaneNeeds both = standing_for({7.5e-3, 0.1});
    both.energy_every = every;
    LaneWorker reference(model, spec, plan, both);
    EXPECT_EQ(energy_per_target(reference), expected);
    ASSERT_EQ(expected.size(), static_cast<std::size_t>(plan.size()));
    EXPECT_GE(expected.back().size(), 2u) << "samples between the targets too";
  }
}
