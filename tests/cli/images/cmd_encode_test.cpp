// clothsim encode: PNG sequences -> a tiled, labelled MP4, and every bad input refused
// with one line, a non-zero exit and no file under the output name.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_process.h"
#include "png_header.h"
#include "render/png_io.h"
#include "render/video/mp4_probe.h"
#include "render/video/tiling.h"

namespace fs = std::filesystem;
using namespace clothsim;
namespace cli = clothsim::testing;
using clothsim::testing::run_clothsim;
using clothsim::testing::scratch_dir;

namespace {

Image solid(int w, int h, Rgba8 c) {
  Image image(w, h);
  fill_rect(image, 0, 0, w, h, c);
  return image;
}

std::string frame_name(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.png", k);
  return name;
}

// `frames` PNGs of one colour (or one colour per frame) in root/name.
std::string write_sequence(const std::string& root, const std::string& name, int frames, int w, int h,
                           const std::vector<Rgba8>& colours) {
  const fs::path dir = fs::path(root) / name;
  fs::create_directories(dir);
  for (int k = 0; k < frames; ++k)
    write_png((dir / frame_name(k)).string(), solid(w, h, colours[std::min<std::size_t>(k, colours.size() - 1)]));
  return dir.string();
}

const Rgba8 kRed{210, 40, 40, 255}, kGreen{40, 190, 60, 255}, kBlue{50, 60, 220, 255},
    kYellow{235, 225, 50, 255};

void expect_colour_near(const std::array<double, 3>& got, Rgba8 want, double tol, const std::string& what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tol) << what << " channel " << c;
}

// No output file, no temporary beside it, one line on stderr naming `needle`.
void expect_refused(const cli::CliResult& r, int code, const std::string& output,
                    const std::string& needle) {
  EXPECT_EQ(r.exit_code, code) << r.err;
  EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(output));
  if (fs::is_directory(fs::path(output).parent_path())) {
    for (const auto& entry : fs::directory_iterator(fs::path(output).parent_path())) {
      EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
    }
  }
}

TEST(CmdEncode, AClipOntoOneOfItsFramesIsRefusedAndTheFrameKept) {
  const std::string root = scratch_dir("encode_onto_frame");
  const std::string dir = write_sequence(root, "a", 3, 32, 24, {kRed});
  const std::string frame = cli::slurp(dir + "/" + frame_name(1));
  const auto r = run_clothsim({"encode", dir, "-o", root + "/a/../a/" + frame_name(1)});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("is a frame of input directory " + dir), std::string::npos) << r.err;
  EXPECT_EQ(cli::slurp(dir + "/" + frame_name(1)), frame);
}

}  // namespace

TEST(CmdEncode, AssemblesFourSequencesIntoALabelledTwoByTwoClip) {
  const std::string root = scratch_dir("encode_2x2");
  const std::vector<Rgba8> colours = {kRed, kGreen, kBlue, kYellow};
  std::vector<std::string> args = {"encode"};
  for (int i = 0; i < 4; ++i)
    args.push_back(write_sequence(root, "tile" + std::to_string(i), 6, 160, 90, {colours[i]}));
  const std::string out = root + "/grid.mp4";
  for (const char* a : {"--layout", "2x2", "--labels", "a,b,c,d", "--fps", "10", "-o"}) args.push_back(a);
  args.push_back(out);
  const auto r = run_clothsim(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const auto info = test::probe_mp4(out);
  EXPECT_EQ(info.codec, "h264");
  EXPECT_EQ(info.pixel_format, "yuv420p");
  EXPECT_EQ(info.width, 2 * 160 + 4);  // two tiles and the gutter
  EXPECT_EQ(info.height, 2 * 90 + 4);
  EXPECT_EQ(info.rate_num, 10);
  EXPECT_EQ(info.rate_den, 1);
  ASSERT_EQ(info.frames.size(), 6u);
  const Image& f = info.frames.back();
  // Tile centres (upper half, away from the labels) in row-major order.
  expect_colour_near(test::mean_rgb(f, 80, 30, 4), kRed, 8, "top-left");
  expect_colour_near(test::mean_rgb(f, 164 + 80, 30, 4), kGreen, 8, "top-right");
  expect_colour_near(test::mean_rgb(f, 80, 94 + 30, 4), kBlue, 8, "bottom-left");
  expect_colour_near(test::mean_rgb(f, 164 + 80, 94 + 30, 4), kYellow, 8, "bottom-right");
  // The label sits at each tile's bottom-left: pixels there are far from the tile colour.
  int far = 0;
  for (int y = 70; y < 88; ++y)
    for (int x = 2; x < 40; ++x) {
      const auto* p = f.pixel(x, y);
      far += std::abs(p[0] - kRed[0]) + std::abs(p[1] - kRed[1]) + std::abs(p[2] - kRed[2]) > 120;
    }
  EXPECT_GT(far, 10) << "label 'a' is visible in the first tile";
}

TEST(CmdEncode, HoldsTheLastFrameOfAShorterSequenceAndSaysSo) {
  const std::string root = scratch_dir("encode_lengths");
  const std::string a = write_sequence(root, "long", 6, 64, 48, {kRed});
  const std::string b = write_sequence(root, "short", 3, 64, 48, {kBlue, kBlue, kGreen});
  const std::string out = root + "/held.mp4";
  const auto r = run_clothsim({"encode", a, b, "--layout", "Nx1", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("holds its last frame after 3 frames"), std::string::npos) << r.err;
  const auto info = test::probe_mp4(out);
  ASSERT_EQ(info.frames.size(), 6u);
  expect_colour_near(test::mean_rgb(info.frames[5], 68 + 32, 10, 3), kGreen, 8, "held frame");
  expect_colour_near(test::mean_rgb(info.frames[5], 32, 10, 3), kRed, 8, "long sequence");
}

TEST(CmdEncode, PadsAnOddSizedGridToEvenDimensions) {
  const std::string root = scratch_dir("encode_odd");
  const std::string a = write_sequence(root, "a", 2, 81, 45, {kRed});
  const std::string b = write_sequence(root, "b", 2, 81, 45, {kBlue});
  const std::string out = root + "/odd.mp4";
  const auto r = run_clothsim({"encode", a, b, "--layout", "2x1", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto info = test::probe_mp4(out);
  EXPECT_EQ(info.width, 2 * 81 + 4);  // 166, already even
  EXPECT_EQ(info.height, 46);         // 45 padded
  EXPECT_EQ(info.frames.size(), 2u);
}

TEST(CmdEncode, RefusesAMissingDirectory) {
  const std::string root = scratch_dir("encode_missing");
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", root + "/nope", "-o", out}), 2, out, root + "/nope");
}

TEST(CmdEncode, RefusesADirectoryWithoutFrames) {
  const std::string root = scratch_dir("encode_empty");
  fs::create_directories(root + "/empty");
  const std::string out = root + "/x.mp4";
  const auto r = run_clothsim({"encode", root + "/empty", "-o", out});
  expect_refused(r, 2, out, "no frames");
  EXPECT_NE(r.err.find(root + "/empty"), std::string::npos);
}

TEST(CmdEncode, RefusesASequenceWithAGap) {
  const std::string root = scratch_dir("encode_gap");
  const std::string dir = write_sequence(root, "gap", 4, 32, 32, {kRed});
  fs::remove(fs::path(dir) / frame_name(2));
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", dir, "-o", out}), 2, out, "frame_00002.png is missing");
}

TEST(CmdEncode, RefusesPngsOfMismatchedSizesNamingTheOddOne) {
  const std::string root = scratch_dir("encode_sizes");
  const std::string dir = write_sequence(root, "mixed", 3, 32, 32, {kRed});
  write_png((fs::path(dir) / frame_name(3)).string(), solid(40, 32, kRed));
  const std::string out = root + "/x.mp4";
  const auto r = run_clothsim({"encode", dir, "-o", out});
  expect_refused(r, 2, out, frame_name(3));
  EXPECT_NE(r.err.find("40x32"), std::string::npos) << r.err;
}

TEST(CmdEncode, RefusesAnUnknownLayoutOrALayoutTooSmall) {
  const std::string root = scratch_dir("encode_layout");
  const std::string a = write_sequence(root, "a", 1, 16, 16, {kRed});
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", a, a, a, "--layout", "diagonal", "-o", out}), 2, out,
                 "unknown layout 'diagonal'");
  expect_refused(run_clothsim({"encode", a, a, a, "--layout", "2x1", "-o", out}), 2, out,
                 "2 cells for 3 tiles");
}

TEST(CmdEncode, RefusesLabelsThatDoNotMatchTheDirectories) {
  const std::string root = scratch_dir("encode_labels");
  const std::string a = write_sequence(root, "a", 1, 16, 16, {kRed});
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", a, a, "--labels", "one", "-o", out}), 2, out,
                 "--labels has 1 names for 2 directories");
}

TEST(CmdEncode, RefusesAnUnwritableOutputBeforeReadingFrames) {
  const std::string root = scratch_dir("encode_unwritable");
  const std::string a = write_sequence(root, "a", 1, 16, 16, {kRed});
  std::ofstream(root + "/plain") << "x";  // a file where a folder would have to be made
  const std::string out = root + "/plain/dir/x.mp4";
  const auto r = run_clothsim({"encode", a, "-o", out});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("cannot make its folder"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(CmdEncode, RefusesBadEncoderOptions) {
  const std::string root = scratch_dir("encode_options");
  const std::string a = write_sequence(root, "a", 1, 16, 16, {kRed});
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", a, "--crf", "99", "-o", out}), 2, out, "crf");
  expect_refused(run_clothsim({"encode", a, "--preset", "ludicrous", "-o", out}), 2, out,
                 "unknown x264 preset 'ludicrous'");
  expect_refused(run_clothsim({"encode", a, "--fps", "0", "-o", out}), 2, out, "fps");
  // A rate whose time base no 32-bit fraction holds: said as a range, not "Invalid argument".
  expect_refused(run_clothsim({"encode", a, "--fps", "1e-9", "-o", out}), 2, out, "fps must be in [0.001, 1000]");
}

TEST(CmdEncode, NoOverwriteRefusesAnExistingClipBeforeReadingAnyFrame) {
  const std::string dir = scratch_dir("encode_no_overwrite");
  const std::string out = dir + "/clip.mp4";
  { std::FILE* f = std::fopen(out.c_str(), "wb"); std::fputs("mine", f); std::fclose(f); }
  const auto r = run_clothsim({"encode", dir + "/no_frames_here", "-n", "-o", out});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("-o/--output: " + out + " exists, and -n/--no-overwrite keeps it"), std::string::npos) << r.err;
  EXPECT_EQ(cli::slurp(out), "mine");
}

TEST(CmdEncode, RefusesAPictureOverMaxMemoryWithTheEncodersShare) {
  const std::string root = scratch_dir("encode_max_memory");
  const std::string a = write_sequence(root, "a", 1, 1024, 1024, {kRed});
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", a, "-o", out, "--max-memory", "100M"}), 2, out,
                 "needs an estimated 228 MB (process 80 MB, tiles 4 MB, frame 1024x1024 4 MB, encoder 140 MB), "
                 "more than --max-memory 100 MB");
}

// A 1 kB file claiming 20000 x 20000 pixels would decode to 1.5 GB: refused from its header.
TEST(CmdEncode, RefusesAHugePngInAFrameFolderFromItsHeaderBeforeDecoding) {
  const std::string root = scratch_dir("encode_huge_png");
  fs::create_directories(root + "/a");
  cli::png_header_only(root + "/a/frame_00000.png", 20000, 20000);  // no pixel data: never decoded
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", root + "/a", "-o", out, "--max-memory", "500M"}), 2, out,
                 "frame 20000x20000 1.49 GB, encoder 43.2 GB), more than --max-memory 500 MB; encode smaller frames");
}

TEST(CmdEncode, RefusesAPngHeaderClaimingMoreThanThePngFormatAllows) {
  const std::string root = scratch_dir("encode_corrupt_header");
  fs::create_directories(root + "/a");
  cli::png_header_only(root + "/a/frame_00000.png", 3000000000u, 2);  // past 2^31 - 1: not a PNG
  const std::string out = root + "/x.mp4";
  expect_refused(run_clothsim({"encode", root + "/a", "-o", out}), 2, out, "corrupt PNG (size 3000000000x2)");
}

// x264 reports a failed allocation on stderr by itself, not through libav's log; it is
// captured while the encoder opens. An address-space limit (ulimit -v) that a 4096 x 4096
// encoder cannot fit in makes the failure real; wherever it strikes first on a machine (x264,
// the PNG decoder), it is one line, exit 1, and nothing under the name.
TEST(CmdEncode, AnEncoderThatCannotAllocateIsOneLineExit1AndLeavesNothing) {
  const std::string root = scratch_dir("encode_no_memory");
  const std::string a = write_sequence(root, "a", 2, 4096, 4096, {kRed, kBlue});
  const std::string out = root + "/x.mp4";
  const auto r = run_clothsim({"encode", a, "-o", out}, "ulimit -v 500000;");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(cli::line_count(r.err), 1) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(cli::only_files(root, {"a"})) << "no temporary beside it";
}
