// clothsim imgdiff as users call it: exit 0 within tolerance, 1 outside, 2 for bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli/cli_process.h"
#include "png_header.h"
#include "render/png_io.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using testing::line_count;
using testing::png_header_only;
using testing::run_clothsim;
using testing::scratch_dir;
using testing::slurp;

Image gradient(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(x * 3), p[1] = static_cast<std::uint8_t>(y * 4), p[2] = 90, p[3] = 255;
    }
  return image;
}

struct Pair {
  std::string dir, a, b;
};

// a.png and b.png of 40x30; b differs from a in `changed` pixels by `amount` in red (red <= 120: no wrap).
Pair write_pair(const std::string& name, int changed, int amount, int bw = 40) {
  Pair p{scratch_dir("imgdiff_" + name), "", ""};
  p.a = p.dir + "/a.png";
  p.b = p.dir + "/b.png";
  const Image a = gradient(40, 30);
  Image b = gradient(bw, 30);
  for (int i = 0; i < changed; ++i) b.pixel(i % bw, i / bw)[0] = static_cast<std::uint8_t>(b.pixel(i % bw, i / bw)[0] + amount);
  write_png(p.a, a);
  write_png(p.b, b);
  return p;
}

TEST(CmdImgdiff, ImagesPastMaxMemoryAreRefusedFromTheirHeadersBeforeDecoding) {
  const std::string dir = scratch_dir("imgdiff_huge");
  const std::string big = png_header_only(dir + "/big.png", 20000, 20000);  // no pixel data: never decoded
  const auto r = run_clothsim({"imgdiff", big, big, "--max-memory", "500M"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("two 20000x20000 images"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("more than --max-memory 500 MB; compare smaller images"), std::string::npos) << r.err;
}

TEST(CmdImgdiff, ImagesOfDifferentSizesAreRefusedFromTheirHeaders) {
  const std::string dir = scratch_dir("imgdiff_sizes");
  const auto r = run_clothsim({"imgdiff", png_header_only(dir + "/a.png", 40, 30), png_header_only(dir + "/b.png", 20000, 20000)});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("is 40x30 but"), std::string::npos) << r.err;
}

TEST(CmdImgdiff, IdenticalImagesAreWithinToleranceAndExitZero) {
  const Pair p = write_pair("same", 0, 0);
  const auto r = run_clothsim({"imgdiff", p.a, p.b});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("rms difference     0.0000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max difference     0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("within tolerance"), std::string::npos) << r.out;
}

TEST(CmdImgdiff, ImagesThatDifferTooMuchExitOne) {
  const Pair p = write_pair("different", 300, 100);  // a quarter of the pixels, 100 levels
  const auto r = run_clothsim({"imgdiff", p.a, p.b});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("max difference     100"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("DIFFERENT"), std::string::npos) << r.out;
}

TEST(CmdImgdiff, TolerancesComeFromTheFlags) {
  const Pair p = write_pair("flags", 3, 40);  // 3 of 1200 pixels: passes the defaults
  EXPECT_EQ(run_clothsim({"imgdiff", p.a, p.b}).exit_code, 0);
  EXPECT_EQ(run_clothsim({"imgdiff", p.a, p.b, "--max-over", "0"}).exit_code, 1);
  EXPECT_EQ(run_clothsim({"imgdiff", p.a, p.b, "--max-over", "0", "--threshold", "40"}).exit_code, 0);
  EXPECT_EQ(run_clothsim({"imgdiff", p.a, p.b, "--max-rms", "0.5"}).exit_code, 1);
}

TEST(CmdImgdiff, WritesAnAmplifiedDiffImageOfTheSameSize) {
  const Pair p = write_pair("diff_out", 50, 10);
  const std::string out = p.dir + "/diff.png";
  const auto r = run_clothsim({"imgdiff", p.a, p.b, "--diff", out});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const Image diff = read_png(out);
  EXPECT_EQ(diff.width, 40);
  EXPECT_EQ(diff.height, 30);
  EXPECT_GT(diff.pixel(0, 0)[0], diff.pixel(39, 29)[0] + 100);  // changed pixel glows, others dim
}

TEST(CmdImgdiff, AMissingImageIsBadInputNamingTheFile) {
  const Pair p = write_pair("missing", 0, 0);
  const std::string absent = p.dir + "/absent.png";
  const auto r = run_clothsim({"imgdiff", p.a, absent});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(absent), std::string::npos) << r.err;
}

TEST(CmdImgdiff, ACorruptImageIsBadInputNamingTheFile) {
  const Pair p = write_pair("corrupt", 0, 0);
  const std::string text = p.dir + "/text.png", cut = p.dir + "/cut.png";
  std::ofstream(text) << "not an image";
  std::filesystem::copy_file(p.a, cut);
  std::filesystem::resize_file(cut, std::filesystem::file_size(cut) / 2);
  for (const std::string& bad : {text, cut}) {
    const auto r = run_clothsim({"imgdiff", bad, p.b});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(bad), std::string::npos) << r.err;
  }
}

TEST(CmdImgdiff, ImagesOfDifferentSizesAreBadInputNamingBoth) {
  const Pair p = write_pair("sizes", 0, 0, 41);
  const auto r = run_clothsim({"imgdiff", p.a, p.b});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("40x30"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("41x30"), std::string::npos) << r.err;
}

TEST(CmdImgdiff, BadFlagsAreBadUsage) {
  const Pair p = write_pair("bad_flags", 0, 0);
  EXPECT_EQ(run_clothsim({"imgdiff", p.a}).exit_code, 2);
  EXPECT_EQ(run_clothsim({"imgdiff", p.a, p.b, "--threshold", "300"}).exit_code, 2);
  EXPECT_EQ(run_clothsim({"imgdiff", p.a, p.b, "--max-over", "1.5"}).exit_code, 2);
}

TEST(CmdImgdiff, ADiffImageThatCannotBeWrittenFailsAndWritesNothing) {
  const Pair p = write_pair("unwritable", 0, 0);
  std::ofstream(p.dir + "/plain") << "x";  // a file where its folder would have to be made
  const std::string out = p.dir + "/plain/dir/diff.png";
  const auto r = run_clothsim({"imgdiff", p.a, p.b, "--diff", out});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(out), std::string::npos) << r.err;
  EXPECT_TRUE(testing::only_files(p.dir, {"a.png", "b.png", "plain"}));
}

TEST(CmdImgdiff, DashOIsTheDiffImageAndNoOverwriteKeepsAnExistingOne) {
  const Pair p = write_pair("dash_o", 50, 10);
  const std::string out = p.dir + "/diff.png";
  ASSERT_EQ(run_clothsim({"imgdiff", p.a, p.b, "-o", out}).exit_code, 0);
  const std::vector<std::uint8_t> first = read_png(out).rgba;
  const Pair q = write_pair("dash_o_other", 0, 0);
  const auto r = run_clothsim({"imgdiff", q.a, q.b, "-n", "--output", out});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("exists, and -n/--no-overwrite keeps it"), std::string::npos) << r.err;
  EXPECT_EQ(read_png(out).rgba, first);
}

TEST(CmdImgdiff, ADiffImageOntoAnInputIsRefusedAndTheInputKept) {
  const Pair p = write_pair("onto_input", 10, 50);
  fs::create_symlink(p.b, p.dir + "/link.png");
  const std::string a = slurp(p.a), b = slurp(p.b);
  for (const std::string& out : {p.a, p.dir + "/./a.png", p.dir + "/link.png"}) {
    const auto r = run_clothsim({"imgdiff", p.a, p.b, "-o", out});
    EXPECT_EQ(r.exit_code, 2) << out;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("an output never replaces an input"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(p.a), a);
  EXPECT_EQ(slurp(p.b), b);
}

TEST(CmdImgdiff, ANanToleranceIsRefused) {
  const Pair p = write_pair("nan", 0, 0);
  for (const std::string option : {"--max-rms", "--max-over"}) {
    const auto r = run_clothsim({"imgdiff", p.a, p.b, option, "nan"});
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_EQ(line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(option + ": must be a number"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace clothsim
