// compare --frames DIR --shard K/N: the parts render, lane by lane, the very PNGs one
// `compare --frames` renders, so `clothsim encode` makes the same clip from either; a part
// refuses what would make its tiles differ (a colour scale from its own lanes' data) and
// the outputs that draw every lane.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_process.h"

namespace clothsim::testing {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> compare(const std::string& frames, const std::vector<std::string>& extra) {
  std::vector<std::string> args{"compare", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--duration", "0.2",
                                "--width", "192", "--height", "108", "--overlay-cost", "work", "--frames", frames};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Every PNG of a lane's folder, in order, as one string.
std::string lane_bytes(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().string());
  std::sort(names.begin(), names.end());
  std::string all;
  for (const std::string& n : names) all += slurp(n);
  return all;
}

void expect_parts_equal_one_process(const std::string& dir, const std::vector<std::string>& look) {
  ASSERT_EQ(run_clothsim(compare(dir + "/one", look)).exit_code, 0);
  for (const char* k : {"1/2", "2/2"}) {
    std::vector<std::string> part = look;
    part.insert(part.end(), {"--shard", k});
    const CliResult r = run_clothsim(compare(dir + "/parts", part));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string("shard ") + k + " of compare: 2 of 4 lanes"), std::string::npos) << r.out;
  }
  std::vector<std::string> lanes;
  for (const auto& e : fs::directory_iterator(dir + "/one")) lanes.push_back(e.path().filename().string());
  ASSERT_EQ(lanes.size(), 4u);
  std::sort(lanes.begin(), lanes.end());
  for (const std::string& lane : lanes) {
    const std::string frames = lane_bytes(dir + "/one/" + lane);
    EXPECT_GT(frames.size(), 0u);
    EXPECT_TRUE(frames == lane_bytes(dir + "/parts/" + lane)) << lane;
  }
  for (const char* from : {"one", "parts"}) {
    std::vector<std::string> encode{"encode"};
    for (const std::string& lane : lanes) encode.push_back(dir + "/" + from + "/" + lane);
    encode.insert(encode.end(), {"--layout", "2x2", "-o", dir + "/" + from + ".mp4"});
    ASSERT_EQ(run_clothsim(encode).exit_code, 0) << from;
  }
  EXPECT_TRUE(slurp(dir + "/one.mp4") == slurp(dir + "/parts.mp4"));
}

TEST(CompareShard, PartsRenderTheFramesAndClipOneProcessRenders) {
  expect_parts_equal_one_process(scratch_dir("compare_shard_checker"), {"--color", "checker"});
}

TEST(CompareShard, ErrorColouredPartsNeedAFixedScaleAndThenMatch) {
  const std::string dir = scratch_dir("compare_shard_error");
  const CliResult data_scale = run_clothsim(compare(dir + "/x", {"--shard", "1/2"}));
  EXPECT_EQ(data_scale.exit_code, 2);
  EXPECT_EQ(line_count(data_scale.err), 1) << data_scale.err;
  EXPECT_NE(data_scale.err.find("give --color-range LO,HI"), std::string::npos) << data_scale.err;
  EXPECT_FALSE(fs::exists(dir + "/x"));
  expect_parts_equal_one_process(dir, {"--color", "error", "--color-range", "1e-6,1e-2"});
}

TEST(CompareShard, APartWritesFramesOnly) {
  const std::string dir = scratch_dir("compare_shard_outputs");
  const CliResult video = run_clothsim(compare(dir + "/x", {"--color", "checker", "--shard", "1/2", "--video",
                                                            dir + "/v.mp4"}));
  EXPECT_EQ(video.exit_code, 2);
  EXPECT_NE(video.err.find("a part writes --frames only"), std::string::npos) << video.err;
  const CliResult no_frames = run_clothsim({"compare", std::string(CLOTHSIM_SCENES_DIR) + "/drape.yaml", "--summary",
                                            dir + "/s.json", "--shard", "1/2"});
  EXPECT_EQ(no_frames.exit_code, 2);
  EXPECT_NE(no_frames.err.find("with --frames DIR only"), std::string::npos) << no_frames.err;
  EXPECT_TRUE(only_files(dir, {}));
}

}  // namespace
}  // namespace clothsim::testing
