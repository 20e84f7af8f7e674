// The reference standing in at the lanes' times (reference_stand.h): served in time order
// across targets, so a lane of a large step (standing far past its target) does not make the
// reference pass a time a lane of a small step needs for a later target.
#include "reference_stand.h"

#include <gtest/gtest.h>

#include <string>

#include "lane_times.h"
#include "scene_parser.h"

using namespace clothsim;
using namespace clothsim::cli;

namespace {

Model small_drape() {
  return build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", {"cloth.particles=[5,5]"}));
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
  clothsim::Run reference(model, IntegratorKind::SymplecticEuler, H);
  ReferenceStand stand(model, reference, steps);
  std::vector<std::int64_t> landed(steps.size(), 0);
  int added = 0, popped = 0;
  const int targets = 13;  // 0 .. 0.4 s
  while (popped < targets) {
    if (stand.front_ready()) {
      std::vector<ReferenceStand::Positions> x;
      const Target target = stand.pop(x);
      ASSERT_EQ(x.size(), steps.size());
      for (std::size_t j = 0; j < steps.size(); ++j) {
        landed[j] = landing_step(target.t, steps[j], landed[j]);
        const double t = static_cast<double>(landed[j]) * steps[j];
        clothsim::Run direct(model, IntegratorKind::SymplecticEuler, H);
        ASSERT_TRUE(direct.advance_to(t));
        const std::vector<double> expected(direct.state().x.data(),
                                           direct.state().x.data() + 3 * model.num_particles);
        ASSERT_TRUE(x[j]);
        EXPECT_EQ(*x[j], expected) << "target " << target.t << " s, lane " << steps[j] << " s at " << t << " s";
      }
      EXPECT_EQ(x[1], x[2]) << "lanes of one step share one copy";
      ++popped;
      continue;
    }
    const double next = added / 30.0;
    if (added < targets && stand.add_before_serving(next)) {
      stand.add(Target{next});
      ++added;
      continue;
    }
    ASSERT_TRUE(stand.serve_next());
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
  ReferenceStand stand(model, reference, {7.5e-4});
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
