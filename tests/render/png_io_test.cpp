#include "render/png_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace clothsim {
namespace {

namespace fs = std::filesystem;

// Reference PNGs made outside the code under test (Python's zlib + struct), 2 x 2, rows top-down:
// RGB  [red, green / blue, white]; grey [0, 85 / 170, 255]; palette [(10,20,30), (200,100,50) / swapped].
const unsigned char kRgb2x2[] = {137, 80, 78, 71, 13, 10, 26, 10, 0, 0, 0, 13, 73, 72, 68, 82, 0, 0, 0, 2, 0, 0, 0, 2, 8, 2, 0, 0, 0, 253, 212, 154, 115, 0, 0, 0, 18, 73, 68, 65, 84, 120, 156, 99, 248, 207, 192, 192, 0, 194, 12, 255, 129, 0, 0, 31, 238, 5, 251, 11, 217, 104, 139, 0, 0, 0, 0, 73, 69, 78, 68, 174, 66, 96, 130};
const unsigned char kGrey2x2[] = {137, 80, 78, 71, 13, 10, 26, 10, 0, 0, 0, 13, 73, 72, 68, 82, 0, 0, 0, 2, 0, 0, 0, 2, 8, 0, 0, 0, 0, 87, 221, 82, 248, 0, 0, 0, 14, 73, 68, 65, 84, 120, 156, 99, 96, 8, 101, 88, 245, 31, 0, 3, 173, 1, 255, 103, 251, 202, 9, 0, 0, 0, 0, 73, 69, 78, 68, 174, 66, 96, 130};
const unsigned char kPalette2x2[] = {137, 80, 78, 71, 13, 10, 26, 10, 0, 0, 0, 13, 73, 72, 68, 82, 0, 0, 0, 2, 0, 0, 0, 2, 8, 3, 0, 0, 0, 69, 104, 253, 22, 0, 0, 0, 6, 80, 76, 84, 69, 10, 20, 30, 200, 100, 50, 119, 160, 179, 156, 0, 0, 0, 12, 73, 68, 65, 84, 120, 156, 99, 96, 96, 4, 66, 0, 0, 12, 0, 3, 43, 99, 203, 80, 0, 0, 0, 0, 73, 69, 78, 68, 174, 66, 96, 130};

std::string scratch(const std::string& name) {
  const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / "png_io" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

template <std::size_t N>
std::string write_bytes(const std::string& path, const unsigned char (&bytes)[N], std::size_t count = N) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(count));
  return path;
}

void expect_pixel(const Image& image, int x, int y, int r, int g, int b) {
  const std::uint8_t* p = image.pixel(x, y);
  EXPECT_EQ(p[0], r) << "at " << x << "," << y;
  EXPECT_EQ(p[1], g) << "at " << x << "," << y;
  EXPECT_EQ(p[2], b) << "at " << x << "," << y;
  EXPECT_EQ(p[3], 255) << "at " << x << "," << y;
}

// A gradient with a distinct value in every pixel and channel of the first rows.
Image test_pattern(int w, int h) {
  Image image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(x * 7 + y);
      p[1] = static_cast<std::uint8_t>(y * 13 + x / 3);
      p[2] = static_cast<std::uint8_t>((x ^ y) * 5);
      p[3] = 255;
    }
  return image;
}

std::vector<std::string> names_in(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

TEST(PngIo, ReadsTheSizeFromTheHeaderAloneAndRefusesWhatIsNotAPng) {
  const std::string dir = scratch("size");
  const std::string path = dir + "/size.png";
  write_png(path, Image(7, 3));
  const PngSize size = read_png_size(path);
  EXPECT_EQ(size.width, 7);
  EXPECT_EQ(size.height, 3);
  const std::string text = dir + "/not.png";
  std::ofstream(text) << "not a png at all, but long enough to hold a header";
  EXPECT_THROW(read_png_size(text), PngError);
  EXPECT_THROW(read_png_size(dir + "/missing.png"), PngError);
}

TEST(PngIo, ReadsAReferenceRgbFileTopRowFirst) {
  const Image image = read_png(write_bytes(scratch("ref_rgb") + "/rgb.png", kRgb2x2));
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 2);
  expect_pixel(image, 0, 0, 255, 0, 0);
  expect_pixel(image, 1, 0, 0, 255, 0);
  expect_pixel(image, 0, 1, 0, 0, 255);
  expect_pixel(image, 1, 1, 255, 255, 255);
}

TEST(PngIo, ReadsGreyAndPaletteFilesAsOpaqueRgba) {
  const std::string dir = scratch("ref_grey_palette");
  const Image grey = read_png(write_bytes(dir + "/grey.png", kGrey2x2));
  expect_pixel(grey, 0, 0, 0, 0, 0);
  expect_pixel(grey, 1, 0, 85, 85, 85);
  expect_pixel(grey, 0, 1, 170, 170, 170);
  expect_pixel(grey, 1, 1, 255, 255, 255);
  const Image palette = read_png(write_bytes(dir + "/palette.png", kPalette2x2));
  expect_pixel(palette, 0, 0, 10, 20, 30);
  expect_pixel(palette, 1, 0, 200, 100, 50);
  expect_pixel(palette, 0, 1, 200, 100, 50);
  expect_pixel(palette, 1, 1, 10, 20, 30);
}

TEST(PngIo, WrittenPixelsReadBackExactlyAtEveryZlibLevel) {
  const std::string dir = scratch("round_trip");
  const Image original = test_pattern(67, 41);  // odd sizes: no row-alignment luck
  for (int level : {0, 1, 2, 3, 9}) {
    const std::string path = dir + "/level" + std::to_string(level) + ".png";
    write_png(path, original, {}, level);
    const Image back = read_png(path);
    ASSERT_EQ(back.width, original.width);
    ASSERT_EQ(back.height, original.height);
    EXPECT_EQ(back.rgba, original.rgba) << "zlib level " << level;
  }
}

TEST(PngIo, StoresMetadataAsTextChunks) {
  const std::string path = scratch("text") + "/meta.png";
  const PngText meta = {{"scene", "drape"}, {"integrator", "rk4"}, {"dt", "0.0001"}, {"t", "2.5"},
                        {"clothsim", "0.1.0"}};
  write_png(path, test_pattern(8, 8), meta);
  PngText back;
  read_png(path, &back);
  EXPECT_EQ(back, meta);
}

TEST(PngIo, ReplacesAnExistingFileAndLeavesNoTemporaries) {
  const std::string dir = scratch("replace");
  write_png(dir + "/a.png", test_pattern(16, 16));
  Image second = test_pattern(16, 16);
  second.pixel(3, 4)[0] = 1;
  write_png(dir + "/a.png", second);
  EXPECT_EQ(read_png(dir + "/a.png").rgba, second.rgba);
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"a.png"});
}

TEST(PngIo, WritingIntoAMissingDirectoryFailsNamingThePathAndLeavesNothing) {
  const std::string dir = scratch("missing_dir");
  const std::string path = dir + "/no/such/dir/a.png";
  try {
    write_png(path, test_pattern(4, 4));
    FAIL() << "expected PngError";
  } catch (const PngError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_TRUE(names_in(dir).empty());
}

TEST(PngIo, WritingBelowARegularFileFails) {
  // A directory that cannot be written even by root: its "parent" is a file.
  const std::string dir = scratch("under_file");
  std::ofstream(dir + "/plain").put('x');
  EXPECT_THROW(write_png(dir + "/plain/a.png", test_pattern(4, 4)), PngError);
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"plain"});
}

TEST(PngIo, RefusesAnEmptyImageAndABadTextKey) {
  const std::string dir = scratch("refuse");
  EXPECT_THROW(write_png(dir + "/empty.png", Image()), PngError);
  EXPECT_THROW(write_png(dir + "/key.png", test_pattern(4, 4), {{"", "value"}}), PngError);
  EXPECT_TRUE(names_in(dir).empty());
}

TEST(PngIo, ReadingAMissingFileFailsNamingIt) {
  const std::string path = scratch("missing") + "/absent.png";
  try {
    read_png(path);
    FAIL() << "expected PngError";
  } catch (const PngError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(PngIo, ReadingAFileThatIsNotAPngFails) {
  const std::string path = scratch("not_png") + "/text.png";
  std::ofstream(path) << "hello, not a picture\n";
  try {
    read_png(path);
    FAIL() << "expected PngError";
  } catch (const PngError& e) {
    EXPECT_NE(std::string(e.what()).find("not a PNG"), std::string::npos) << e.what();
  }
}

TEST(PngIo, ReadingATruncatedOrCorruptedPngFails) {
  const std::string dir = scratch("corrupt");
  EXPECT_THROW(read_png(write_bytes(dir + "/truncated.png", kRgb2x2, 40)), PngError);
  unsigned char flipped[sizeof kRgb2x2];
  std::copy(std::begin(kRgb2x2), std::end(kRgb2x2), flipped);
  flipped[45] ^= 0xFF;  // inside the IDAT data: its CRC no longer matches
  EXPECT_THROW(read_png(write_bytes(dir + "/bad_crc.png", flipped)), PngError);
}

}  // namespace
}  // namespace clothsim
