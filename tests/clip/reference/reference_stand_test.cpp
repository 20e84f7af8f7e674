// The reference standing in at the lanes' times (reference_stand.h): served in time order
// across targets, so a lane of a large step (standing far past its target) does not make the
// reference pass a time a lane of a small step needs for a later target.
#include "clip/reference/reference_stand.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "clip/reference/lane_times.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

using namespace clothsim;
using namespace clothsim::clip;

namespace {

Model small_drape() {
  return build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", {"cloth.particles=[5,5]"}));
}

struct Handed {
  Target target;
  std::vector<ReferenceStand::Positions> x;  // per lane
};

// Serves `stand` over `plan` as LaneWorker does (ReferenceStand::add_before_serving decides
// when a target is added), calling each(targets added, handed over) before every turn;
// returns the targets as handed over, in order.
std::vector<Handed> serve_all(ReferenceStand& stand, const TargetPlan& plan,
                              const std::function<void(std::size_t, std::size_t)>& each = {}) {
  std::vector<Handed> handed;
  TargetPlan::Cursor cursor(plan);
  Target next;
  bool more = cursor.next(next);
  std::size_t added = 0;
  for (;;) {
    if (each) each(added, handed.size());
    if (stand.front_ready()) {
      handed.emplace_back();
      handed.back().target = stand.pop(handed.back().x);
      continue;
    }
    if (more && stand.add_before_serving(next.t)) {
      stand.add(next);
      ++added;
      more = cursor.next(next);
      continue;
    }
    if (stand.empty()) break;
    if (!stand.serve_next()) {
      ADD_FAILURE() << "the reference stopped";
      break;
    }
  }
  return handed;
}

}  // namespace

TEST(ReferenceStand, ServesEveryLaneAtItsOwnTimeAcrossTargetsInTimeOrder) {
  const Model model = small_drape();
  const double H = 1e-4;
  // Lanes of 0.3 s and 0.05 s (multiples of H: every time they stand at is a step of the
  // reference, so its positions there are a run's state to the bit) and frames at 30 Hz: the
  // first target needs 0.3 s for one lane and 0.05 s for the other, and the next eight need
  // the second at 0.1 .. 0.3 s, before the reference may go past them. A third lane of the
  // second's step shares its positions (one copy a target, not one a lane).
  const std::vector<double> steps{0.3, 0.05, 0.05};
  const TargetPlan plan(0.4, 30.0, true, {});  // 13 targets, 0 .. 0.4 s
  clothsim::Run reference(model, IntegratorKind::SymplecticEuler, H);
  ReferenceStand stand(model, reference, steps, plan.last_time());
  std::vector<std::int64_t> landed(steps.size(), 0);
  const std::vector<Handed> handed = serve_all(stand, plan);
  ASSERT_EQ(handed.size(), 13u);
  for (const auto& [target, x] : handed) {
    ASSERT_EQ(x.size(), steps.size());
    for (std::size_t j = 0; j < steps.size(); ++j) {
      landed[j] = landing_step(target.t, steps[j], landed[j]);
      const double t = static_cast<double>(landed[j]) * steps[j];
      clothsim::Run direct(model, IntegratorKind::SymplecticEuler, H);
      ASSERT_TRUE(direct.advance_to(t));
      const std::vector<double> expected(direct.state().x.data(), direct.state().x.data() + 3 * model.num_particles);
      ASSERT_TRUE(x[j]);
      EXPECT_EQ(*x[j], expected) << "target " << target.t << " s, lane " << steps[j] << " s at " << t << " s";
    }
    EXPECT_EQ(x[1], x[2]) << "lanes of one step share one copy";
  }
  EXPECT_TRUE(stand.empty());
  EXPECT_LE(reference.state().t, 0.6 + H) << "no further than the last time a lane stands at";
}

TEST(ReferenceStand, InterpolatesBetweenItsStepsToWithinTheMethodsError) {
  // The drape's cloth falling free (no ball: a contact inside an interval makes the motion
  // unsmooth there, and the interpolant first order). A lane of 7.5e-4 s against a reference
  // of 1e-4 s: its times fall between the reference's steps. A run at 2.5e-5 s lands on them
  // exactly and is far more accurate than either: the interpolated positions agree with it to
  // the reference's own error, not to 7.5e-4 s of motion at about 2 m/s.
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                             {"cloth.particles=[5,5]", "spheres=[]"}));
  clothsim::Run reference(model, IntegratorKind::Rk4, 1e-4);
  ReferenceStand stand(model, reference, {7.5e-4}, 0.2);
  stand.add(Target{0.2});
  while (!stand.front_ready()) ASSERT_TRUE(stand.serve_next());
  std::vector<ReferenceStand::Positions> x;
  stand.pop(x);
  const double t = static_cast<double>(landing_step(0.2, 7.5e-4, 0)) * 7.5e-4;
  ASSERT_NE(step_at(t, 1e-4), 0) << "the lane's time must fall between the reference's steps";
  ASSERT_EQ(step_at(t, 1e-4), -1);
  clothsim::Run fine(model, IntegratorKind::Rk4, 2.5e-5);
  ASSERT_TRUE(fine.advance_to(t));
  double largest = 0.0, moved = 0.0;
  for (int i = 0; i < 3 * model.num_particles; ++i) {
    largest = std::max(largest, std::abs((*x[0])[i] - fine.state().x.data()[i]));
    moved = std::max(moved, std::abs(fine.state().v.data()[i]) * 7.5e-4);
  }
  EXPECT_GT(moved, 1e-4) << "the cloth moves: an offset in time would show";
  EXPECT_LT(largest, 1e-6);
}

TEST(ReferenceStand, ItsCheckAtTwiceTheStepEstimatesAFirstOrderReferencesOwnError) {
  // The ball-less cloth falling free under symplectic Euler, first order as a projected
  // contact is: the run at twice the step is twice as far from the truth, so their distance
  // (the estimate) is the reference's own error, to within the error's next order. The truth:
  // a run at 1/16 the step.
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                             {"cloth.particles=[5,5]", "spheres=[]"}));
  const double H = 1e-4;
  const IntegratorKind method = IntegratorKind::SymplecticEuler;
  clothsim::Run reference(model, method, H), check(model, method, 2 * H);
  ReferenceStand stand(model, reference, {1e-3}, 0.3);
  stand.check_against(check);
  EXPECT_TRUE(std::isnan(stand.estimated_error())) << "none before any step is checked";
  stand.add(Target{0.3});
  while (!stand.front_ready()) ASSERT_TRUE(stand.serve_next());
  std::vector<ReferenceStand::Positions> x;
  stand.pop(x);
  EXPECT_DOUBLE_EQ(check.state().t, reference.state().t) << "checked where the reference stands";
  clothsim::Run truth(model, method, H / 16);
  ASSERT_TRUE(truth.advance_to(reference.state().t));
  const double own_error = analysis::largest_particle_distance(model, reference.state(), truth.state());
  EXPECT_GT(own_error, 1e-6) << "far above round-off";
  EXPECT_GT(stand.estimated_error(), 0.8 * own_error);
  EXPECT_LT(stand.estimated_error(), 1.5 * own_error);
}

TEST(ReferenceStand, ServesADroppedLaneNoLongerAndRunsNoFurtherThanTheLiveLanesNeed) {
  // A lane of 20 s on a 0.5 s clip stands at 20 s from the second frame on; it diverged there
  // (as rk4@20 does on the drape), and once it is dropped the reference serves the lane of
  // 0.01 s alone: every frame of it, and no further than its last landing (0.5 s) and one of
  // the reference's own steps. It used to run to 20 s for a lane that could use none of it.
  const Model model = small_drape();
  const double H = 1e-4;
  const TargetPlan plan(0.5, 30.0, true, {});
  clothsim::Run reference(model, IntegratorKind::SymplecticEuler, H);
  ReferenceStand stand(model, reference, {20.0, 0.01}, plan.last_time());
  EXPECT_DOUBLE_EQ(stand.horizon(), 20.0) << "while the lane of 20 s is live, 20 s may be needed";
  std::size_t waiting_at_drop = 0;
  const auto handed = serve_all(stand, plan, [&](std::size_t added, std::size_t popped) {
    // Dropped as the reference is about to run to 20 s for it (the pipeline drops it when its
    // frozen frame arrives, with the second target), every target added and waiting for it.
    if (waiting_at_drop == 0 && stand.next_time() == 20.0 && added == 16) {
      waiting_at_drop = added - popped;
      stand.drop_lane(0);
    }
  });
  EXPECT_EQ(waiting_at_drop, 15u) << "targets 1 .. 15 waited for the lane of 20 s";
  EXPECT_DOUBLE_EQ(stand.horizon(), 0.5);
  ASSERT_EQ(handed.size(), 16u) << "every target goes out";
  EXPECT_TRUE(handed[0].x[0]) << "served before it was dropped";
  for (std::size_t k = 0; k < handed.size(); ++k) {
    EXPECT_TRUE(handed[k].x[1]) << "the live lane at target " << k;
    if (k > 0) {
      EXPECT_FALSE(handed[k].x[0]) << "the dropped lane at target " << k;
    }
  }
  EXPECT_LE(reference.state().t, 0.5 + H + 1e-12);
  stand.drop_lane(1);
  EXPECT_EQ(stand.horizon(), -std::numeric_limits<double>::infinity()) << "no live lane: nothing is needed";
}

TEST(ReferenceStand, TheTargetsWaitingAndThePositionsTheyHoldStayWithinTheEstimatesBound) {
  // compare's memory estimate counts ReferenceStand::waiting_bound targets' positions, one copy
  // per distinct lane step each: a lane of 0.3 s keeps the frames of the next 0.3 s waiting.
  const Model model = small_drape();
  const std::vector<double> steps{0.3, 0.05, 1e-3, 1e-3};
  const TargetPlan plan(2.0, 30.0, true, {0.55}, 1.27);  // a sheet column and a still between frames
  clothsim::Run reference(model, IntegratorKind::SymplecticEuler, 1e-4);
  ReferenceStand stand(model, reference, steps, plan.last_time());
  std::size_t most_waiting = 0, most_held = 0;
  const auto handed = serve_all(stand, plan, [&](std::size_t added, std::size_t popped) {
    most_waiting = std::max(most_waiting, added - popped);
    most_held = std::max(most_held, stand.positions_held());
  });
  ASSERT_EQ(handed.size(), static_cast<std::size_t>(plan.size()));
  const long bound = ReferenceStand::waiting_bound(steps, plan);
  EXPECT_GE(most_waiting, 9u) << "the lane of 0.3 s keeps 9 frames or more waiting";
  EXPECT_LE(static_cast<long>(most_waiting), bound);
  EXPECT_LE(bound, 9 + 2 + 2) << "the largest step's frames, rounding, the column and the still";
  EXPECT_GE(most_held, 9u);
  EXPECT_LE(static_cast<long>(most_held), bound * 3) << "one copy per distinct step (three here) a target";
}

TEST(ReferencePositionsBytes, CountTheFramesALargeLaneStepKeepsWaitingOneCopyPerDistinctStep) {
  // A 512 x 512 drape, a clip of 0.5 s at 30 frames/s: 16 targets. Lanes at 1e-4 s keep a
  // target or two waiting; a lane of 20 s keeps all of them (each frame's positions for the
  // lanes of 1e-4 s wait for its landing at 20 s). Two copies of the reference's state, one
  // copy of the positions (24 B per particle) per distinct step, per target waiting and per
  // frame of the worker's queue (4), the one being pushed and the pipeline's.
  const SceneDef scene = load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", {"cloth.particles=[512,512]"});
  const TargetPlan clip(0.5, 30.0, true, {});
  const double copy = 24.0 * 512 * 512;
  const double small = reference_positions_bytes(scene, {1e-4, 1e-4, 1e-4}, clip, 4);
  EXPECT_DOUBLE_EQ(small, copy * (4 + (2 + 4 + 2) * 1)) << "one distinct step, two targets waiting";
  const double large = reference_positions_bytes(scene, {20.0, 1e-4}, clip, 4);
  EXPECT_DOUBLE_EQ(large, copy * (4 + (16 + 4 + 2) * 2)) << "every target waiting, two distinct steps";
  EXPECT_GT(large, 250e6) << "the positions that were not counted: 288 MB (MiB) here";
}
