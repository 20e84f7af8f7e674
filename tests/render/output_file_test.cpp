// OutputFile: nothing under the name until commit(), nothing at all when dropped, the
// system's reason when the file cannot be made.
#include "render/output_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace clothsim {
namespace {

namespace fs = std::filesystem;

std::string fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(CLOTHSIM_TEST_OUTPUT_DIR) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

int entries(const std::string& dir) {
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

std::string contents(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(OutputFile, HasNoNameAtAllUntilCommitted) {
  const std::string dir = fresh_dir("output_file_commit");
  OutputFile file(dir + "/a.csv");
  std::fputs("x,y\n1,2\n", file.stream());
  std::fflush(file.stream());
  EXPECT_EQ(entries(dir), 0) << "not even a hidden temporary (O_TMPFILE)";
  EXPECT_FALSE(file.named_fallback());
  file.commit();
  EXPECT_EQ(contents(dir + "/a.csv"), "x,y\n1,2\n");
  EXPECT_EQ(entries(dir), 1);
}

TEST(OutputFile, DroppedUncommittedLeavesNothing) {
  const std::string dir = fresh_dir("output_file_drop");
  {
    OutputFile file(dir + "/a.csv");
    std::fputs("half a file", file.stream());
  }
  EXPECT_EQ(entries(dir), 0);
}

TEST(OutputFile, ReplacesAnExistingFileWholeAndLeavesNoTemporary) {
  const std::string dir = fresh_dir("output_file_replace");
  for (const char* text : {"first\n", "second\n"}) {
    OutputFile file(dir + "/a.csv");
    std::fputs(text, file.stream());
    file.commit();
  }
  EXPECT_EQ(contents(dir + "/a.csv"), "second\n");
  EXPECT_EQ(entries(dir), 1);
}

TEST(OutputFile, CanBeReopenedByNameWhileWriting) {
  const std::string dir = fresh_dir("output_file_reopen");
  OutputFile file(dir + "/a.bin");
  std::fputs("abc", file.stream());
  std::fflush(file.stream());
  EXPECT_EQ(contents(file.reopen_path()), "abc") << "libavformat's +faststart reads the file back";
}

TEST(OutputFile, SaysThePathAndTheSystemsReason) {
  try {
    OutputFile file(std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/no/such/dir/a.csv");
    FAIL() << "expected OutputFileError";
  } catch (const OutputFileError& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot write " + std::string(CLOTHSIM_TEST_OUTPUT_DIR) + "/no/such/dir/a.csv: No such file or directory");
  }
}

TEST(OutputFile, HiddenTempNamesAreUniqueBesideThePathWithItsExtension) {
  const std::string a = hidden_temp_name("out/clip.mp4"), b = hidden_temp_name("out/clip.mp4");
  EXPECT_NE(a, b);
  EXPECT_EQ(fs::path(a).parent_path(), "out");
  EXPECT_EQ(fs::path(a).extension(), ".mp4");
  EXPECT_EQ(fs::path(a).filename().string().rfind(".clip.partial-", 0), 0u) << a;
}

}  // namespace
}  // namespace clothsim
