// make_video_sink: the FrameSink `run --video` and `compare --video` stream into.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli/cli_process.h"
#include "clip/common/cli_common.h"
#include "clip/frames/frame_sink.h"
#include "render/synthetic_frames.h"
#include "render/video/mp4_probe.h"

namespace fs = std::filesystem;
using namespace clothsim;
using namespace clothsim::clip;

using clothsim::testing::grey_image;

TEST(VideoSink, OpensOnTheFirstFrameAndAppearsOnlyAtFinish) {
  const std::string dir = clothsim::testing::scratch_dir("video_sink_ok");
  const std::string path = dir + "/clip.mp4";
  auto sink = make_video_sink(path, VideoOptions{24.0, 23, "ultrafast"});
  for (int k = 0; k < 4; ++k) sink->add(k, k / 24.0, grey_image(96, 54, static_cast<std::uint8_t>(40 * k)));
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(sink->written(), "") << "nothing under the name before finish()";
  sink->finish();
  EXPECT_EQ(sink->written(), path);
  sink->abandon();  // after finish(): the clip is complete and stays
  EXPECT_EQ(sink->written(), path);
  const auto info = test::probe_mp4(path, false);
  EXPECT_EQ(info.width, 96);
  EXPECT_EQ(info.height, 54);
  EXPECT_EQ(info.rate_num, 24);
  EXPECT_EQ(info.frames.size(), 4u);
  EXPECT_TRUE(clothsim::testing::only_files(dir, {"clip.mp4"}));
}

TEST(VideoSink, LeavesNothingWhenDestroyedUnfinished) {
  const std::string dir = clothsim::testing::scratch_dir("video_sink_abandoned");
  {
    auto sink = make_video_sink(dir + "/clip.mp4", VideoOptions{});
    sink->add(0, 0.0, grey_image(32, 32, 128));
  }
  EXPECT_TRUE(clothsim::testing::only_files(dir, {}));
  auto sink = make_video_sink(dir + "/clip.mp4", VideoOptions{});
  sink->add(0, 0.0, grey_image(32, 32, 128));
  sink->abandon();
  EXPECT_EQ(sink->written(), "");
  EXPECT_TRUE(clothsim::testing::only_files(dir, {}));
}

TEST(VideoSink, RefusesBadOptionsAsUsageAndAFolderItCannotMakeAsRuntimeFailure) {
  const std::string dir = clothsim::testing::scratch_dir("video_sink_bad");
  EXPECT_THROW(make_video_sink(dir + "/a.mp4", VideoOptions{30.0, 20, "turbo"}), UsageError);
  EXPECT_THROW(make_video_sink(dir + "/a.mp4", VideoOptions{30.0, 70, "veryfast"}), UsageError);
  std::ofstream(dir + "/plain") << "x";  // a file where its folder would have to be made
  EXPECT_THROW(make_video_sink(dir + "/plain/sub/a.mp4", VideoOptions{}), RuntimeFailure);
  EXPECT_NO_THROW(make_video_sink(dir + "/made/a.mp4", VideoOptions{}));  // a missing folder is made
}

TEST(VideoSink, RefusesToFinishAClipWithoutFrames) {
  const std::string dir = clothsim::testing::scratch_dir("video_sink_empty");
  auto sink = make_video_sink(dir + "/empty.mp4", VideoOptions{});
  EXPECT_THROW(sink->finish(), RuntimeFailure);
  EXPECT_FALSE(fs::exists(dir + "/empty.mp4"));
}
