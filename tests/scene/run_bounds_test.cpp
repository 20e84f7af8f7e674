// Steps and frames bounded at validation, computed in floating point (no overflow).
#include "scene/run_bounds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scene/scene_parser.h"

namespace clothsim {
namespace {

TEST(RunBounds, AcceptsEveryRunUpToTheLimits) {
  EXPECT_EQ(run_bounds_problem(5.0, 1e-4, 30.0), "");
  EXPECT_EQ(run_bounds_problem(1.0, 1e-9, 30.0), "") << "1e9 steps: the limit itself";
  EXPECT_EQ(run_bounds_problem(0.0, 1e-4, 30.0), "");
}

TEST(RunBounds, RefusesTooManyStepsOrFramesWithoutOverflow) {
  EXPECT_NE(run_bounds_problem(1.0, 1e-12, 30.0).find("1e+12 steps, more than the limit of 1e+09"), std::string::npos);
  EXPECT_NE(run_bounds_problem(1e300, 1e-4, 30.0).find("steps"), std::string::npos);
  EXPECT_NE(run_bounds_problem(1e300, 1e-300, 30.0).find("inf steps"), std::string::npos);
  EXPECT_NE(run_bounds_problem(1e6, 1.0, 30.0).find("3e+07 output frames"), std::string::npos);
}

TEST(RunBounds, ACountJustOverItsLimitReadsOverItWithTheFrameAtZeroShown) {
  EXPECT_EQ(run_bounds_problem(1e4, 0.01, 1000.0),
            "duration x render.fps + 1 = 10000 s x 1000 + 1 = 10000001 output frames, more than the limit of "
            "10000000 (shorten the duration or lower render.fps)");
  EXPECT_EQ(run_bounds_problem(1.0000001, 1e-9, 0.0),
            "duration / dt = 1.0000001 s / 1e-09 s = 1.0000001e+09 steps, more than the limit of 1e+09 (raise dt "
            "or shorten the duration)");
  // Whatever the numbers, the message's count is over the limit it states.
  for (const double excess : {1e-9, 1e-6, 1e-3, 0.5, 1.0, 10.0, 1e4}) {
    for (const bool frames : {false, true}) {
      const std::string text = frames ? run_bounds_problem((kMaxFrames - 1.0 + excess) / 30.0, 1.0, 30.0)
                                      : run_bounds_problem(kMaxSteps + excess * 100.0, 1.0, 0.0);
      if (text.empty()) continue;  // the excess was lost to rounding: within the limit
      const auto number_before = [&](const std::string& word) {
        const std::size_t end = text.find(word);
        const std::size_t begin = text.rfind(' ', end - 2) + 1;
        return std::stod(text.substr(begin, end - begin));
      };
      const std::size_t of = text.find("the limit of ") + 13;
      const double limit = std::stod(text.substr(of, text.find(' ', of) - of));
      EXPECT_GT(number_before(frames ? " output frames" : " steps"), limit) << text;
    }
  }
}

TEST(RunBounds, AreCheckedWhenASceneIsParsedNamingTheKey) {
  try {
    parse_scene("duration: 1\ndt: 1.0e-12\ncloth: {particles: [3, 3]}\n", "s.yaml");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line, 2);
    EXPECT_EQ(e.key, "dt");
  }
  try {
    parse_scene("dt: 1.0e-3\ncloth: {particles: [3, 3]}\n", "s.yaml", {"duration=1e300"});
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("--set duration=1e300"), std::string::npos) << e.what();
  }
}

TEST(RunBounds, TooManyFramesNameDurationOrTheFpsThatMadeThem) {
  try {
    parse_scene("duration: 1.0e5\ndt: 1\nrender: {fps: 1000}\ncloth: {particles: [3, 3]}\n", "s.yaml");
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line, 1);
    EXPECT_EQ(e.key, "duration");
    EXPECT_NE(std::string(e.what()).find("1e+08 output frames"), std::string::npos) << e.what();
  }
  try {
    parse_scene("dt: 1\nrender: {fps: 1000}\ncloth: {particles: [3, 3]}\n", "s.yaml", {"duration=1e5"});
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("--set duration=1e5"), std::string::npos) << e.what();
  }
}

TEST(RunBounds, AreLeftToTheCallerThatReplacesDurationOrDt) {
  EXPECT_NO_THROW(parse_scene("duration: 1\ndt: 1.0e-12\ncloth: {particles: [3, 3]}\n", "s.yaml", {},
                              /*bound_run=*/false));
}

}  // namespace
}  // namespace clothsim
