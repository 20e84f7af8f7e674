// OutputFile: nothing under the name until commit(), nothing at all when dropped, the
// system's reason when the file cannot be made.
#include "io/output_file.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

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

TEST(OutputFile, StreamsIntoACharacterDeviceAndLeavesItOne) {
  OutputFile file("/dev/null");
  EXPECT_TRUE(file.streaming());
  std::fputs("x,y\n", file.stream());
  file.commit();
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "replaced by a regular file";
}

TEST(OutputFile, StreamsIntoAFifoWithoutReplacingIt) {
  const std::string dir = fresh_dir("output_file_fifo");
  const std::string fifo = dir + "/pipe.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = contents(fifo); });  // opening blocks until both ends exist
  {
    OutputFile file(fifo);
    std::fputs("streamed", file.stream());
    file.commit();
  }
  reader.join();
  EXPECT_EQ(received, "streamed");
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(entries(dir), 1);
}

TEST(OutputFile, WritesIntoAnInheritedDescriptorByItsPath) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  for (const std::string& path : {"/dev/fd/" + std::to_string(fds[1]), "/proc/self/fd/" + std::to_string(fds[1])}) {
    OutputFile file(path);
    EXPECT_TRUE(file.streaming()) << path;
    std::fputs("ab", file.stream());
    file.commit();
  }
  ::close(fds[1]);
  char buf[8] = {};
  EXPECT_EQ(::read(fds[0], buf, sizeof buf), 4);
  EXPECT_EQ(std::string(buf), "abab");
  ::close(fds[0]);
}

TEST(OutputFile, FollowsASymlinkAndReplacesItsTarget) {
  const std::string dir = fresh_dir("output_file_symlink");
  { std::ofstream(dir + "/real.csv") << "old\n"; }
  fs::create_symlink("real.csv", dir + "/link.csv");
  fs::create_symlink("sub/../new.csv", dir + "/dangling.csv");
  fs::create_directory(dir + "/sub");
  for (const char* name : {"/link.csv", "/dangling.csv"}) {
    OutputFile file(dir + name);
    EXPECT_FALSE(file.streaming());
    std::fputs("new\n", file.stream());
    file.commit();
  }
  EXPECT_TRUE(fs::is_symlink(dir + "/link.csv"));
  EXPECT_TRUE(fs::is_symlink(dir + "/dangling.csv"));
  EXPECT_EQ(contents(dir + "/real.csv"), "new\n");
  EXPECT_EQ(contents(dir + "/new.csv"), "new\n");
  EXPECT_EQ(entries(dir), 5) << "real, new, sub and the two links: no temporary";
}

TEST(OutputFile, RefusesADirectoryAndASymlinkLoop) {
  const std::string dir = fresh_dir("output_file_refuse");
  fs::create_symlink("b", dir + "/a");
  fs::create_symlink("a", dir + "/b");
  EXPECT_THROW(OutputFile(dir + "/a"), OutputFileError);
  EXPECT_THROW(OutputFile file(dir), OutputFileError);
}

TEST(OutputFile, NoClobberRefusesANameMadeDuringTheWrite) {
  const std::string dir = fresh_dir("output_file_no_clobber");
  set_no_clobber(true);
  OutputFile file(dir + "/a.csv");
  std::fputs("ours", file.stream());
  { std::ofstream(dir + "/a.csv") << "theirs"; }  // another run got there first
  EXPECT_THROW(file.commit(), OutputFileError);
  set_no_clobber(false);
  EXPECT_EQ(contents(dir + "/a.csv"), "theirs");
  EXPECT_EQ(entries(dir), 1);
}

TEST(OutputFile, UnlinkFirstReplacesWithoutEverMakingAHiddenName) {
  const std::string dir = fresh_dir("output_file_unlink_first");
  for (const char* text : {"first\n", "second\n"}) {
    OutputFile file(dir + "/frame_00000.png", Replace::kUnlinkFirst);
    std::fputs(text, file.stream());
    file.commit();
  }
  EXPECT_EQ(contents(dir + "/frame_00000.png"), "second\n");
  EXPECT_EQ(entries(dir), 1);
}

TEST(OutputFile, ResolvesWhatAPathNames) {
  EXPECT_EQ(resolve_output("-").fd, 1);
  EXPECT_EQ(resolve_output("/dev/stdout").fd, 1);
  EXPECT_EQ(resolve_output("/dev/fd/7").fd, 7);
  EXPECT_TRUE(resolve_output("/dev/null").streams);
  EXPECT_FALSE(resolve_output("/no/such/file.csv").streams);
  EXPECT_EQ(resolve_output("/no/such/file.csv").path, "/no/such/file.csv");
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
