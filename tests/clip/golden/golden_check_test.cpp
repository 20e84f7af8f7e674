// golden check's comparison of one render (src/clip/golden/golden_check.h): a match clears old
// evidence, a mismatch or a missing golden leaves the render (and the amplified diff) beside it.
#include "clip/golden/golden_check.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "render/png_io.h"

namespace clothsim::clip {
namespace {

namespace fs = std::filesystem;

struct GoldenDir : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("golden_check_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
  static Image grey(int value) {
    Image image(8, 6);
    for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = (i % 4 == 3) ? 255 : value;
    return image;
  }
};

TEST_F(GoldenDir, EvidenceGoesBesideTheGoldenOrIntoTheFailuresFolder) {
  GoldenOptions o;
  EXPECT_EQ(evidence_path(o, "g/drape_t1500ms.png", "actual"), "g/drape_t1500ms.actual.png");
  o.failures_dir = "out";
  EXPECT_EQ(evidence_path(o, "g/drape_t1500ms.png", "diff"), "out/drape_t1500ms.diff.png");
}

TEST_F(GoldenDir, AMatchPassesAndRemovesTheEvidenceOfAnEarlierFailure) {
  const std::string golden = (dir / "a_t100ms.png").string();
  write_png(golden, grey(100));
  write_png((dir / "a_t100ms.actual.png").string(), grey(0));  // left by a failed check before
  std::vector<std::string> evidence;
  const GoldenVerdict v = check_one(GoldenOptions{}, golden, grey(101), DiffTolerance{}, evidence);
  EXPECT_TRUE(v.ok) << v.problem;
  EXPECT_LE(v.rms, 1.0) << "one level per channel at most";
  EXPECT_TRUE(evidence.empty());
  EXPECT_FALSE(fs::exists(dir / "a_t100ms.actual.png"));
}

TEST_F(GoldenDir, AMismatchWritesTheRenderAndTheDiffAndSaysByHowMuch) {
  const std::string golden = (dir / "a_t100ms.png").string();
  write_png(golden, grey(100));
  std::vector<std::string> evidence;
  const GoldenVerdict v = check_one(GoldenOptions{}, golden, grey(140), DiffTolerance{}, evidence);
  EXPECT_FALSE(v.ok);
  EXPECT_EQ(v.max, 40);
  EXPECT_EQ(v.over_fraction, 1.0) << "every pixel past the threshold of 16";
  EXPECT_NE(v.problem.find("max 40"), std::string::npos) << v.problem;
  EXPECT_EQ(evidence.size(), 2u);
  EXPECT_TRUE(fs::exists(v.diff));
  EXPECT_EQ(read_png(v.actual).rgba, grey(140).rgba) << "the render as it was made";
}

TEST_F(GoldenDir, AMissingGoldenOrOneOfAnotherSizeIsAProblemWithTheRenderKept) {
  std::vector<std::string> evidence;
  const std::string missing = (dir / "b_t0ms.png").string();
  const GoldenVerdict gone = check_one(GoldenOptions{}, missing, grey(0), DiffTolerance{}, evidence);
  EXPECT_FALSE(gone.ok);
  EXPECT_NE(gone.problem.find("missing"), std::string::npos);
  EXPECT_TRUE(fs::exists(gone.actual));
  const std::string small = (dir / "c_t0ms.png").string();
  write_png(small, Image(4, 4));
  const GoldenVerdict sized = check_one(GoldenOptions{}, small, grey(0), DiffTolerance{}, evidence);
  EXPECT_EQ(sized.problem, "golden is 4x4, the render 8x6");
}

TEST_F(GoldenDir, UpdateNamesEveryStagedImageOnlyWhenCommitAllRuns) {
  GoldenWork work;
  for (const char* name : {"a.png", "b.png"}) {
    work.staged.push_back(std::make_unique<OutputFile>((dir / name).string()));
    std::fputs("image", work.staged.back()->stream());
  }
  EXPECT_FALSE(fs::exists(dir / "a.png")) << "staged images are nameless until every one is made";
  ::testing::internal::CaptureStdout();
  commit_all(work);
  EXPECT_NE(::testing::internal::GetCapturedStdout().find("wrote " + (dir / "b.png").string()), std::string::npos);
  EXPECT_TRUE(fs::exists(dir / "a.png"));
  EXPECT_TRUE(fs::exists(dir / "b.png"));
}

}  // namespace
}  // namespace clothsim::clip
