// The states a reference run kept before it knew the lanes' steps (reference_history.h): any
// step it passed is replayed from them to the bit, and a stand given them serves what a stand
// over a run that never went ahead serves.
#include "clip/reference/reference_history.h"

#include <gtest/gtest.h>

#include <string>

#include "clip/reference/reference_stand.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

using namespace clothsim;
using namespace clothsim::clip;

namespace {

// The drape at 5 x 5, ball and all: contacts make a replay that took one step differently show.
Model small_drape() {
  return build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", {"cloth.particles=[5,5]"}));
}

State state_at_step(const Model& model, IntegratorKind kind, double h, std::int64_t k) {
  clothsim::Run run(model, kind, h);
  EXPECT_TRUE(run.advance_to(static_cast<double>(k) * h));
  EXPECT_EQ(run.state().step, k);
  return run.state();
}

// Runs `run` ahead over `plan`'s targets as LaneWorker does before the steps are known.
void run_ahead(clothsim::Run& run, ReferenceHistory& history, const TargetPlan& plan) {
  history.keep(run.state());
  TargetPlan::Cursor cursor(plan);
  for (Target t; cursor.next(t);) {
    const std::int64_t k = ReferenceHistory::keep_step(t.t, run.dt());
    if (k <= run.state().step) continue;
    ASSERT_TRUE(run.advance_to(static_cast<double>(k) * run.dt()));
    history.keep(run.state());
  }
}

// Every target's positions, per lane, as a stand serves them in time order.
std::vector<std::vector<ReferenceStand::Positions>> serve_all(ReferenceStand& stand, const TargetPlan& plan) {
  std::vector<std::vector<ReferenceStand::Positions>> handed;
  TargetPlan::Cursor cursor(plan);
  Target next;
  bool more = cursor.next(next);
  for (;;) {
    if (stand.front_ready()) {
      handed.emplace_back();
      stand.pop(handed.back());
    } else if (more && stand.add_before_serving(next.t)) {
      stand.add(next);
      more = cursor.next(next);
    } else if (stand.empty()) {
      break;
    } else if (!stand.serve_next()) {
      ADD_FAILURE() << "the reference stopped";
      break;
    }
  }
  return handed;
}

}  // namespace

TEST(ReferenceHistory, KeepsAStepBeforeAnyALaneStandingAtOrAfterTheTargetReads) {
  EXPECT_EQ(ReferenceHistory::keep_step(0.0, 2.5e-5), 0);
  EXPECT_EQ(ReferenceHistory::keep_step(1e-5, 2.5e-5), 0);
  const double t = 1.0 / 30.0, H = 2.5e-5;
  const std::int64_t k = ReferenceHistory::keep_step(t, H);
  EXPECT_LE(static_cast<double>(k + 1) * H, t - 1e-6 * 1.0) << "before a lane of 1 s landing at t less its tolerance";
  EXPECT_GE(k, static_cast<std::int64_t>(t / H) - 3) << "and only a few steps before: a replay is short";
}

TEST(ReferenceHistory, ReplaysAnyStepItPassedToTheBit) {
  const Model model = small_drape();
  const double h = 1e-4;
  clothsim::Run run(model, IntegratorKind::Rk4, h);
  ReferenceHistory history(model, IntegratorKind::Rk4, h);
  history.keep(run.state());
  for (std::int64_t k : {200, 500, 900}) {  // the ball reached (contacts) by then
    ASSERT_TRUE(run.advance_to(static_cast<double>(k) * h));
    history.keep(run.state());
  }
  EXPECT_THROW(history.keep(run.state()), std::logic_error) << "steps increase";
  // Forward within a kept interval, onto a kept step, across one, and then restarted from a
  // later kept state: each the run's own state.
  for (std::int64_t k : {3, 150, 151, 200, 201, 499, 650, 651, 901}) {
    const State direct = state_at_step(model, IntegratorKind::Rk4, h, k);
    const State& replayed = history.at(k);
    ASSERT_EQ(replayed.step, k);
    EXPECT_EQ(replayed.t, direct.t);
    EXPECT_TRUE(replayed.x == direct.x) << "positions at step " << k;
    EXPECT_TRUE(replayed.v == direct.v) << "velocities at step " << k;
  }
  EXPECT_EQ(history.first_step(), 900) << "the states before the one it replays from are forgotten";
  EXPECT_THROW(history.at(899), std::logic_error);
}

TEST(ReferenceStand, ServesFromTheStatesKeptAheadWhatItServesFromARunThatWaited) {
  // Lanes at the reference's steps and between them (7.5e-4 s, interpolated), one larger than
  // the frame interval: the reference ran ahead over the first 0.3 s before it knew them, then
  // serves the whole 0.5 s; every position equals, to the bit, what a reference that knew the
  // steps from the start serves.
  const Model model = small_drape();
  const double H = 1e-4;
  const std::vector<double> steps{1e-4, 7.5e-4, 0.05};
  const TargetPlan plan(0.5, 30.0, true, {}), ahead(0.3, 30.0, true, {});
  clothsim::Run waited(model, IntegratorKind::Rk4, H);
  ReferenceStand plain(model, waited, steps, plan.last_time());
  const auto expected = serve_all(plain, plan);
  clothsim::Run went_ahead(model, IntegratorKind::Rk4, H);
  ReferenceHistory history(model, IntegratorKind::Rk4, H);
  run_ahead(went_ahead, history, ahead);
  ASSERT_GE(went_ahead.state().t, 0.29);
  ReferenceStand replaying(model, went_ahead, steps, plan.last_time(), &history);
  const auto served = serve_all(replaying, plan);
  ASSERT_EQ(served.size(), expected.size());
  ASSERT_EQ(served.size(), 16u);
  for (std::size_t k = 0; k < served.size(); ++k)
    for (std::size_t lane = 0; lane < steps.size(); ++lane) {
      ASSERT_TRUE(served[k][lane] && expected[k][lane]);
      EXPECT_EQ(*served[k][lane], *expected[k][lane]) << "target " << k << ", lane of " << steps[lane] << " s";
    }
  EXPECT_EQ(went_ahead.totals().steps, waited.totals().steps) << "the replays are not the run's steps";
}
