// Where a run lands and the reference between its steps (lane_times.h): the landing step is
// the one a Run really stops on, and the interpolant is exact on cubics, which is what makes
// it fourth order.
#include "clip/reference/lane_times.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/run/simulation.h"
#include "scene/build_model.h"
#include "scene/scene_parser.h"

using namespace clothsim;
using namespace clothsim::clip;

TEST(LaneTimes, LandsOnTheStepARunStopsOn) {
  const Model model = build_model(load_scene(std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml",
                                             {"cloth.particles=[5,5]"}));
  // Steps that divide the frame times, steps that do not, and steps in fractions.
  for (const double h : {1e-4, 3e-4, 7e-4, 2.5e-5, 1.0 / 30.0, 1.0 / 120.0, 0.0333333}) {
    clothsim::Run run(model, IntegratorKind::ImplicitEuler, h);  // stable at every step here
    std::int64_t landed = 0;
    for (int frame = 1; frame <= 12; ++frame) {
      const double target = frame / 30.0;
      landed = landing_step(target, h, landed);
      ASSERT_TRUE(run.advance_to(target));
      EXPECT_EQ(landed, run.state().step) << "h = " << h << ", t = " << target;
    }
    // A target already passed: the run stays where it is.
    EXPECT_EQ(landing_step(0.1, h, landed), landed) << h;
  }
}

TEST(LaneTimes, FindsAStepOnlyWithinRoundingOfItsTime) {
  EXPECT_EQ(step_at(4 * 2.5e-5, 2.5e-5), 4);
  EXPECT_EQ(step_at(1e-4, 2.5e-5), 4) << "k h and the time it is written as differ in the last bits";
  EXPECT_EQ(step_at(0.0, 2.5e-5), 0);
  EXPECT_EQ(step_at(1.1e-4, 2.5e-5), -1);
  EXPECT_EQ(step_at(0.2002, 1e-4), 2002);
  EXPECT_EQ(step_at(0.20021, 1e-4), -1);
}

// Samples every 0.1 s up to each target, none at or past it (the target's own is the
// frame's), counting on across targets; a target within rounding of a sample takes it.
TEST(LaneTimes, EnergySamplesFallBelowEachTargetAndCountOn) {
  long sample = 0;
  EXPECT_EQ(energy_samples_before(0.25, 0.1, sample), (std::vector<double>{0.0, 0.1, 0.2}));
  EXPECT_EQ(sample, 3);
  EXPECT_EQ(energy_samples_before(0.3 + 1e-12, 0.1, sample), std::vector<double>{});
  EXPECT_EQ(sample, 3);
  EXPECT_EQ(energy_samples_before(0.5, 0.1, sample).size(), 2u);  // 0.3 and 0.4
  EXPECT_EQ(sample, 5);
}

TEST(LaneTimes, HermiteInterpolationIsExactOnCubicsAndMeetsItsEnds) {
  // x(t) = a + b t + c t^2 + d t^3 per coordinate, v = x'.
  const double a[3] = {0.3, -1.0, 2.0}, b[3] = {1.5, 0.0, -4.0}, c[3] = {-9.8, 2.0, 0.5}, d[3] = {3.0, -7.0, 1.0};
  const auto x_at = [&](double t, std::vector<double>& x, std::vector<double>& v) {
    x.resize(3);
    v.resize(3);
    for (int i = 0; i < 3; ++i) {
      x[i] = a[i] + t * (b[i] + t * (c[i] + t * d[i]));
      v[i] = b[i] + t * (2.0 * c[i] + 3.0 * t * d[i]);
    }
  };
  const double ta = 0.2, tb = 0.2 + 2.5e-2;
  std::vector<double> xa, va, xb, vb, x, v, out;
  x_at(ta, xa, va);
  x_at(tb, xb, vb);
  for (const double t : {ta, 0.2 + 1e-3, 0.21, 0.2 + 2.4e-2, tb}) {
    hermite_positions(xa, va, ta, xb, vb, tb, t, out);
    x_at(t, x, v);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(out[i], x[i], 1e-14) << "t = " << t << ", coordinate " << i;
  }
  hermite_positions(xa, va, ta, xb, vb, tb, ta, out);
  EXPECT_EQ(out, xa) << "at its start, the start";
}
