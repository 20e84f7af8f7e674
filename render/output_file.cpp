#include "output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace clothsim {

namespace fs = std::filesystem;

namespace {

std::string directory_of(const std::string& path) {
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}

[[noreturn]] void fail(const std::string& path, int error) {
  throw OutputFileError("cannot write " + path + ": " + std::strerror(error));
}

// O_TMPFILE's refusals that mean "not on this file system", as opposed to a real error
// (no such directory, no permission, no space), which the fallback would only repeat.
bool tmpfile_unsupported(int error) { return error == EOPNOTSUPP || error == EISDIR || error == EINVAL; }

}  // namespace

std::string hidden_temp_name(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  const std::string name = "." + p.stem().string() + ".partial-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + p.extension().string();
  return (p.has_parent_path() ? p.parent_path() / name : fs::path(name)).string();
}

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    p += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

OutputFile::OutputFile(std::string path) : path_(std::move(path)) {
  if (path_.empty()) throw OutputFileError("cannot write an output with an empty path");
  // 0666 less the umask, like any file the user makes (mkstemp's 0600 would surprise).
  fd_ = ::open(directory_of(path_).c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
  if (fd_ >= 0) return;
  if (!tmpfile_unsupported(errno)) fail(path_, errno);
  temp_ = hidden_temp_name(path_);
  fd_ = ::open(temp_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd_ < 0) {
    const int error = errno;
    temp_.clear();
    fail(path_, error);
  }
}

OutputFile::~OutputFile() {
  if (!committed_) discard();
}

void OutputFile::discard() {
  if (stream_) std::fclose(stream_);  // closes fd_ too
  else if (fd_ >= 0) ::close(fd_);
  stream_ = nullptr;
  fd_ = -1;
  if (!temp_.empty()) ::unlink(temp_.c_str());
}

std::FILE* OutputFile::stream() {
  if (!stream_ && fd_ >= 0) {
    stream_ = ::fdopen(fd_, "w+b");
    if (!stream_) fail(path_, errno);
  }
  return stream_;
}

std::string OutputFile::reopen_path() const {
  return temp_.empty() ? "/proc/self/fd/" + std::to_string(fd_) : temp_;
}

void OutputFile::commit() {
  if (committed_) return;
  if (stream_ && (std::fflush(stream_) != 0 || std::ferror(stream_))) {
    const int error = errno ? errno : EIO;
    discard();
    fail(path_, error);
  }
  if (temp_.empty()) {
    // linkat through /proc needs no privilege (AT_EMPTY_PATH would need CAP_DAC_READ_SEARCH).
    const std::string self = "/proc/self/fd/" + std::to_string(fd_);
    if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, path_.c_str(), AT_SYMLINK_FOLLOW) != 0) {
      if (errno != EEXIST) {
        const int error = errno;
        discard();
        fail(path_, error);
      }
      // The name is taken (a rerun): link beside it and rename over it, which is atomic.
      temp_ = hidden_temp_name(path_);
      if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temp_.c_str(), AT_SYMLINK_FOLLOW) != 0) {
        const int error = errno;
        temp_.clear();
        discard();
        fail(path_, error);
      }
    }
  }
  if (!temp_.empty() && std::rename(temp_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    discard();
    fail(path_, error);
  }
  temp_.clear();  // the data has its name now
  const int close_result = stream_ ? std::fclose(stream_) : ::close(fd_);
  const int error = errno;
  stream_ = nullptr;
  fd_ = -1;
  if (close_result != 0) {  // a network file system may report a failed write only here
    ::unlink(path_.c_str());
    fail(path_, error);
  }
  committed_ = true;
}

}  // namespace clothsim
