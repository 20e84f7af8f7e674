// The PNG sequence sink (src/clip/frames/png_sequence_sink.cpp), directly and through
// `clothsim run --frames`.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "cli/cli_process.h"
#include "clip/frames/frame_sink.h"
#include "render/png_io.h"
#include "render/synthetic_frames.h"

namespace clothsim {
namespace {

using testing::line_count;
using testing::run_clothsim;
using testing::scratch_dir;

const std::string kDrape = std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml";

std::vector<std::string> small_run(const std::string& frames_dir) {
  return {"run", kDrape, "--duration", "0.1", "--frames", frames_dir,
          "--set", "render.width=96", "--set", "render.height=54"};
}

TEST(PngSequenceSink, WritesOneNumberedPngPerOutputFrameWithItsTimeAsText) {
  const std::string dir = scratch_dir("png_sink_frames") + "/nested/frames";  // created as needed
  const auto r = run_clothsim(small_run(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 30 fps over 0.1 s: t = 0, 1/30, 2/30, 3/30.
  const std::vector<std::string> names = {"frame_00000.png", "frame_00001.png", "frame_00002.png", "frame_00003.png"};
  EXPECT_TRUE(testing::only_files(dir, names));  // and no temporaries left behind
  for (std::size_t k = 0; k < names.size(); ++k) {
    PngText text;
    const Image frame = read_png(dir + "/" + names[k], &text);
    EXPECT_EQ(frame.width, 96);
    EXPECT_EQ(frame.height, 54);
    std::map<std::string, std::string> meta(text.begin(), text.end());
    EXPECT_EQ(meta["scene"], "drape");
    EXPECT_EQ(meta["integrator"], "symplectic_euler");
    ASSERT_TRUE(meta.count("t")) << names[k];
    EXPECT_NEAR(std::stod(meta["t"]), k / 30.0, 1e-4) << names[k];
  }
}

TEST(PngSequenceSink, AFramesDirectoryThatCannotBeMadeFailsBeforeSimulating) {
  const std::string dir = scratch_dir("png_sink_blocked");
  std::ofstream(dir + "/plain_file") << "x";  // a directory cannot be made under a file, even by root
  const std::string frames = dir + "/plain_file/frames";
  const auto r = run_clothsim(small_run(frames));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(frames), std::string::npos) << r.err;
  EXPECT_TRUE(testing::only_files(dir, {"plain_file"}));
}

TEST(PngSequenceSink, SaysWhatItWroteWithoutChangingAnything) {
  // written() is a query: asked after finish(), and again, it names the same PNGs, all of
  // which stay (it was abandon(), an action, that answered this before).
  const std::string dir = scratch_dir("png_sink_written") + "/frames";
  auto sink = clip::make_png_sequence_sink(dir, {});
  for (int k = 0; k < 3; ++k) sink->add(k, k / 30.0, testing::grey_image(16, 8));
  sink->finish();
  EXPECT_EQ(sink->written(), "3 PNGs in " + dir);
  EXPECT_EQ(sink->written(), "3 PNGs in " + dir) << "asking twice changes nothing";
  EXPECT_TRUE(testing::only_files(dir, {"frame_00000.png", "frame_00001.png", "frame_00002.png"}));
}

TEST(PngSequenceSink, AFolderRemovedMeanwhileIsNotReportedAsKept) {
  const std::string dir = scratch_dir("png_sink_removed") + "/frames";
  auto sink = clip::make_png_sequence_sink(dir, {});
  sink->add(0, 0.0, testing::grey_image(16, 8));
  sink->finish();
  std::filesystem::remove_all(dir);
  EXPECT_EQ(sink->written(), "");
}

TEST(PngSequenceSink, AbandonedItKeepsTheWholePngsAndSaysSo) {
  const std::string dir = scratch_dir("png_sink_abandoned") + "/frames";
  auto sink = clip::make_png_sequence_sink(dir, {});
  sink->add(0, 0.0, testing::grey_image(16, 8));
  sink->finish();  // (the one frame is on disk: abandon() may not drop it from the queue)
  sink->abandon();
  EXPECT_EQ(sink->written(), "1 PNG in " + dir);
  EXPECT_TRUE(testing::only_files(dir, {"frame_00000.png"}));
}

TEST(PngSequenceSink, AbandonedBeforeAnyFrameItRemovesTheDirectoryItMadeAndNamesNothing) {
  const std::string parent = scratch_dir("png_sink_abandoned_empty");
  auto sink = clip::make_png_sequence_sink(parent + "/frames", {});
  EXPECT_EQ(sink->written(), "");
  sink->abandon();
  EXPECT_EQ(sink->written(), "");
  EXPECT_TRUE(testing::only_files(parent, {})) << "the directory it made, empty, goes";
}

}  // namespace
}  // namespace clothsim
