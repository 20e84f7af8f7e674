#include "render/video/video_writer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "render/video/mp4_probe.h"

namespace fs = std::filesystem;
using clothsim::Image;
using clothsim::VideoError;
using clothsim::VideoWriter;
using clothsim::VideoWriterOptions;
using clothsim::test::mean_rgb;
using clothsim::test::probe_mp4;

namespace {

std::string out_path(const std::string& name) {
  fs::create_directories(CLOTHSIM_TEST_OUTPUT_DIR "/video");
  const std::string path = std::string(CLOTHSIM_TEST_OUTPUT_DIR "/video/") + name;
  fs::remove(path);
  return path;
}

Image solid(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto* p = image.pixel(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    }
  return image;
}

// Four quadrants of distinct saturated colours: chroma is where yuv420p and the
// BT.709 matrix would go wrong (swapped planes, BT.601 coefficients, wrong range).
Image quadrants(int w, int h) {
  Image image = solid(w, h, 0, 0, 0);
  const std::uint8_t colours[4][3] = {{200, 40, 40}, {40, 180, 60}, {50, 70, 210}, {230, 220, 60}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int q = (y >= h / 2) * 2 + (x >= w / 2);
      auto* p = image.pixel(x, y);
      p[0] = colours[q][0], p[1] = colours[q][1], p[2] = colours[q][2];
    }
  return image;
}

// No file but `path` itself has its stem in its name (no ".stem.partial-PID-N.mp4", no
// "stem.mp4.PID.N.tmp" of the older scheme).
bool no_temporaries_beside(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  const std::string stem = fs::path(path).stem().string();
  for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path())) {
    const std::string other = entry.path().filename().string();
    if (other != name && other.find(stem) != std::string::npos) return false;
  }
  return true;
}

}  // namespace

TEST(VideoWriter, WritesH264Yuv420pAtTheRequestedSizeRateAndFrameCount) {
  const std::string path = out_path("basic.mp4");
  VideoWriter writer(path, 160, 90, VideoWriterOptions{30.0, 20, "ultrafast"});
  for (int k = 0; k < 15; ++k) writer.write(solid(160, 90, 10 * k, 100, 200 - 10 * k));
  writer.finish();
  EXPECT_EQ(writer.frames_written(), 15);

  const auto info = probe_mp4(path);
  EXPECT_EQ(info.codec, "h264");
  EXPECT_EQ(info.pixel_format, "yuv420p");
  EXPECT_EQ(info.width, 160);
  EXPECT_EQ(info.height, 90);
  EXPECT_EQ(info.rate_num, 30);
  EXPECT_EQ(info.rate_den, 1);
  EXPECT_EQ(info.frames.size(), 15u);
}

TEST(VideoWriter, TagsTheStreamBt709LimitedRangeAndPutsTheIndexFirst) {
  const std::string path = out_path("tags.mp4");
  VideoWriter writer(path, 64, 64, VideoWriterOptions{25.0, 23, "ultrafast"});
  for (int k = 0; k < 5; ++k) writer.write(quadrants(64, 64));
  writer.finish();
  const auto info = probe_mp4(path, /*decode_pictures=*/false);
  EXPECT_EQ(info.color_space, "bt709");
  EXPECT_EQ(info.color_primaries, "bt709");
  EXPECT_EQ(info.color_transfer, "bt709");
  EXPECT_EQ(info.color_range, "tv");
  EXPECT_TRUE(info.index_first) << "+faststart should move the moov box before mdat";
}

TEST(VideoWriter, KeepsAFractionalFrameRateAsAnExactRational) {
  const std::string path = out_path("ntsc.mp4");
  VideoWriter writer(path, 32, 32, VideoWriterOptions{29.97, 23, "ultrafast"});
  for (int k = 0; k < 6; ++k) writer.write(solid(32, 32, 90, 90, 90));
  writer.finish();
  const auto info = probe_mp4(path, false);
  EXPECT_NEAR(static_cast<double>(info.rate_num) / info.rate_den, 29.97, 1e-9);
  EXPECT_EQ(info.frames.size(), 6u);
}

TEST(VideoWriter, SolidColoursSurviveEncodingInTheirPlaces) {
  const std::string path = out_path("colours.mp4");
  const Image input = quadrants(160, 90);
  VideoWriter writer(path, 160, 90, VideoWriterOptions{30.0, 18, "ultrafast"});
  for (int k = 0; k < 3; ++k) writer.write(input);
  writer.finish();
  const auto info = probe_mp4(path);
  ASSERT_EQ(info.frames.size(), 3u);
  const Image& decoded = info.frames.back();
  for (int q = 0; q < 4; ++q) {
    const int x = (q % 2) ? 120 : 40, y = (q / 2) ? 67 : 22;
    const auto got = mean_rgb(decoded, x, y, 4);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], input.pixel(x, y)[c], 6.0) << "quadrant " << q << " channel " << c;
  }
}

TEST(VideoWriter, PadsOddSizesToEvenByRepeatingTheEdge) {
  const std::string path = out_path("odd.mp4");
  const Image input = quadrants(161, 91);
  VideoWriter writer(path, 161, 91, VideoWriterOptions{30.0, 18, "ultrafast"});
  EXPECT_EQ(writer.encoded_width(), 162);
  EXPECT_EQ(writer.encoded_height(), 92);
  for (int k = 0; k < 3; ++k) writer.write(input);
  writer.finish();
  const auto info = probe_mp4(path);
  EXPECT_EQ(info.width, 162);
  EXPECT_EQ(info.height, 92);
  ASSERT_EQ(info.frames.size(), 3u);
  // The bottom-right quadrant's colour continues into the padded column and row.
  const auto corner = mean_rgb(info.frames.back(), 161, 91, 0);
  const auto* expected = input.pixel(160, 90);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(corner[c], expected[c], 12.0) << "channel " << c;
}

TEST(VideoWriter, ShowsNothingUnderTheNameUntilFinish) {
  const std::string path = out_path("atomic.mp4");
  VideoWriter writer(path, 32, 32, VideoWriterOptions{30.0, 23, "ultrafast"});
  writer.write(solid(32, 32, 1, 2, 3));
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(no_temporaries_beside(path)) << "written to a nameless O_TMPFILE";
  writer.finish();
  EXPECT_TRUE(fs::exists(path));
  EXPECT_TRUE(no_temporaries_beside(path));
  EXPECT_EQ(probe_mp4(path).frames.size(), 1u) << "+faststart read the nameless file back";
}

TEST(VideoWriter, ReplacesAnExistingFileWhole) {
  const std::string path = out_path("replaced.mp4");
  for (int run = 0; run < 2; ++run) {
    VideoWriter writer(path, 32, 32, VideoWriterOptions{30.0, 23, "ultrafast"});
    for (int k = 0; k <= run; ++k) writer.write(solid(32, 32, 1, 2, 3));
    writer.finish();
  }
  EXPECT_EQ(probe_mp4(path).frames.size(), 2u);
  EXPECT_TRUE(no_temporaries_beside(path));
}

TEST(VideoWriter, RemovesItsTemporaryWhenDestroyedWithoutFinish) {
  const std::string path = out_path("abandoned.mp4");
  {
    VideoWriter writer(path, 32, 32, VideoWriterOptions{30.0, 23, "ultrafast"});
    for (int k = 0; k < 4; ++k) writer.write(solid(32, 32, 9, 9, 9));
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(no_temporaries_beside(path));
}

TEST(VideoWriter, RefusesAFrameOfTheWrongSizeNamingTheFile) {
  const std::string path = out_path("wrong_size.mp4");
  VideoWriter writer(path, 32, 32, VideoWriterOptions{30.0, 23, "ultrafast"});
  try {
    writer.write(solid(34, 32, 0, 0, 0));
    FAIL() << "expected VideoError";
  } catch (const VideoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("34x32"), std::string::npos) << e.what();
  }
}

TEST(VideoWriter, FailsOnAMissingDirectoryWithThePathAndTheReason) {
  const std::string path = CLOTHSIM_TEST_OUTPUT_DIR "/no/such/dir/clip.mp4";
  try {
    VideoWriter writer(path, 32, 32);
    FAIL() << "expected VideoError";
  } catch (const VideoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("No such file or directory"), std::string::npos) << what;
  }
}

TEST(VideoWriter, RejectsOutOfRangeOptionsBeforeOpeningAnything) {
  const std::string path = out_path("bad_options.mp4");
  EXPECT_THROW(VideoWriter(path, 32, 32, VideoWriterOptions{30.0, 52, "veryfast"}), VideoError);
  EXPECT_THROW(VideoWriter(path, 32, 32, VideoWriterOptions{0.0, 20, "veryfast"}), VideoError);
  EXPECT_THROW(VideoWriter(path, 32, 32, VideoWriterOptions{30.0, 20, "warp"}), VideoError);
  EXPECT_THROW(VideoWriter(path, 0, 32), VideoError);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(no_temporaries_beside(path));
}

TEST(VideoWriter, KnowsX264PresetsByName) {
  EXPECT_TRUE(clothsim::is_x264_preset("veryfast"));
  EXPECT_TRUE(clothsim::is_x264_preset("medium"));
  EXPECT_FALSE(clothsim::is_x264_preset("fastest"));
  EXPECT_EQ(clothsim::even_size(161), 162);
  EXPECT_EQ(clothsim::even_size(160), 160);
}
