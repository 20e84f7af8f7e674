// The scale study: refined scenes keep the sheet's total mass, the CSV has its columns, and
// the fitted exponent is the slope of cost against particles.
#include "study/scale_study.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "test_support.h"

namespace clothsim::analysis {
namespace {

using testing::scene_path;

TEST(ScaleScenes, KeepTheSheetsTotalMassAndSize) {
  const auto sizes = scale_scenes(scene_path("drape.yaml"), {"cloth.particle_mass=2"}, {4, 8, 16});
  ASSERT_EQ(sizes.size(), 3u);
  for (const ScaleScene& s : sizes) {
    EXPECT_EQ(s.scene.cloth.nx, s.side);
    EXPECT_EQ(s.scene.cloth.ny, s.side);
    EXPECT_NEAR(s.scene.cloth.particle_mass * s.side * s.side, 2.0 * 16, 1e-12);  // the first size's total
    EXPECT_EQ(s.scene.cloth.size_x, sizes.front().scene.cloth.size_x);
    EXPECT_EQ(s.scene.cloth.size_y, sizes.front().scene.cloth.size_y);
  }
}

TEST(ScaleScenes, RefuseSizesThatDoNotIncrease) {
  EXPECT_THROW(scale_scenes(scene_path("drape.yaml"), {}, {8, 8}), StudyError);
  EXPECT_THROW(scale_scenes(scene_path("drape.yaml"), {}, {1, 8}), StudyError);
  EXPECT_THROW(scale_scenes(scene_path("drape.yaml"), {}, {}), StudyError);
}

TEST(ScaleExponent, IsTheLogLogSlopeOverFinishedRuns) {
  std::vector<ScalePoint> points;
  for (int side : {8, 16, 32}) {
    ScalePoint p;
    p.particles = side * side;
    p.simulated = 0.5;
    p.totals.cpu_seconds = 1e-6 * std::pow(p.particles, 1.5) * p.simulated;  // cost ~ n^1.5
    p.finished = true;
    points.push_back(p);
  }
  EXPECT_NEAR(scale_exponent(points, 0), 1.5, 1e-12);
  points.back().finished = false;  // a run that stopped early says nothing of its cost
  points.back().totals.cpu_seconds *= 100;
  EXPECT_NEAR(scale_exponent(points, 0), 1.5, 1e-12);
  EXPECT_TRUE(std::isnan(scale_exponent(points, 1)));  // no runs of lane 1
}

TEST(ScaleStudy, RunsEveryLaneAtEverySizeWithItsIterationsAndMemory) {
  ScaleSpec spec;
  spec.sizes = scale_scenes(scene_path("drape.yaml"), {}, {6, 12});
  spec.lanes = {{"implicit_euler@1/60", IntegratorKind::ImplicitEuler, 1.0 / 60},
                {"symplectic_euler@1/48000", IntegratorKind::SymplecticEuler, 1.0 / 48000}};
  spec.duration = 2.0 / 60;
  const std::vector<ScalePoint> points = scale_study(spec, {});
  ASSERT_EQ(points.size(), 4u);
  for (const ScalePoint& p : points) {
    EXPECT_TRUE(p.finished) << p.reason;
    EXPECT_NEAR(p.simulated, spec.duration, 1e-9);
    EXPECT_EQ(p.particles, p.side * p.side);
    EXPECT_GT(p.memory_estimate, 0.0);
    EXPECT_GE(p.peak_rss, 0.0);
    if (spec.lanes[p.lane].kind == IntegratorKind::ImplicitEuler) {
      EXPECT_EQ(p.totals.steps, 2);
      EXPECT_GE(p.newton_per_step(), 1.0);  // a drape step is never converged at its first guess
      EXPECT_GT(p.linear_per_newton(), 0.0);
    } else {
      EXPECT_EQ(p.newton_per_step(), 0.0);
    }
  }
  EXPECT_LT(points[0].memory_estimate, points[2].memory_estimate);  // 36 particles against 144
  // The CSV: its header's columns in every row, the lane's spelling first.
  const std::string header = scale_csv_header();
  const auto count = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
  EXPECT_EQ(header.rfind("lane,side,particles,particle_mass,dt,duration,", 0), 0u);
  for (const char* column : {"cpu_per_sim_second", "newton_per_step", "linear_per_newton", "memory_estimate_mb",
                             "peak_rss_mb"})
    EXPECT_NE(header.find(column), std::string::npos) << column;
  for (const ScalePoint& p : points) {
    const std::string row = scale_csv_row(p, spec.lanes, spec.duration);
    EXPECT_EQ(count(row), count(header)) << row;
    EXPECT_EQ(row.rfind(spec.lanes[p.lane].name + ",", 0), 0u) << row;
  }
}

}  // namespace
}  // namespace clothsim::analysis
