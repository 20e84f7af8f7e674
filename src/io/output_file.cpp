#include "output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <vector>

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

[[noreturn]] void fail_exists(const std::string& path) {
  throw OutputFileError("cannot write " + path + ": it exists (made during the run), and -n/--no-overwrite keeps it");
}

// O_TMPFILE's refusals that mean "not on this file system", as opposed to a real error
// (no such directory, no permission, no space), which the fallback would only repeat.
bool tmpfile_unsupported(int error) { return error == EOPNOTSUPP || error == EISDIR || error == EINVAL; }

std::optional<int> number_after(const std::string& path, const std::string& prefix) {
  if (path.size() <= prefix.size() || path.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  int n = 0;
  for (std::size_t i = prefix.size(); i < path.size(); ++i) {
    if (path[i] < '0' || path[i] > '9' || n > 1000000) return std::nullopt;
    n = n * 10 + (path[i] - '0');
  }
  return n;
}

// The descriptor a path names in this process ("-", /dev/stdout, /dev/fd/N, /proc/self/fd/N),
// by its spelling: a container's /dev may lack the symlinks, and /proc/self/fd/N's link text
// ("pipe:[123]") names nothing that could be opened.
std::optional<int> descriptor_of(const std::string& path) {
  if (path == "-" || path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  if (path == "/dev/stdin") return 0;
  for (const std::string& prefix : {std::string("/dev/fd/"), std::string("/proc/self/fd/"),
                                   std::string("/proc/thread-self/fd/"),
                                   "/proc/" + std::to_string(::getpid()) + "/fd/"})
    if (const auto n = number_after(path, prefix)) return n;
  return std::nullopt;
}

// The named fallback under -n: the name must still be free at this instant. renameat2's flag
// where the file system has it, else link() (which never replaces) and unlink.
bool rename_no_replace(const std::string& from, const std::string& to) {
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) return true;
  if (errno != EINVAL && errno != ENOSYS) return false;
  if (::link(from.c_str(), to.c_str()) != 0) return false;
  ::unlink(from.c_str());
  return true;
}

struct ProtectedInput {
  dev_t dev;
  ino_t ino;
  std::string what, path;
};
std::mutex g_inputs_mutex;
std::vector<ProtectedInput> g_inputs;

// The input `st` is, if it is one.
std::optional<ProtectedInput> protected_input(const struct stat& st) {
  std::lock_guard<std::mutex> lock(g_inputs_mutex);
  for (const ProtectedInput& in : g_inputs)
    if (in.dev == st.st_dev && in.ino == st.st_ino) return in;
  return std::nullopt;
}

std::mutex g_stdout_mutex;
int g_stdout_fd = -1;  // where standard output's data goes once claimed
std::atomic<bool> g_no_clobber{false};
std::atomic<long> g_committed{0};
static_assert(std::atomic<long>::is_always_lock_free, "read from a signal handler");

}  // namespace

OutputTarget resolve_output(const std::string& path) {
  std::string p = path;
  for (int hops = 0; hops < 40; ++hops) {  // the kernel's own limit on a chain of symlinks
    if (const auto fd = descriptor_of(p)) return {p, true, *fd};
    struct stat st {};
    if (::lstat(p.c_str(), &st) != 0) {
      if (errno == ENOENT || errno == ENOTDIR) return {p, false, -1};  // a new name, or no such folder (said later)
      fail(path, errno);
    }
    if (!S_ISLNK(st.st_mode)) return {p, !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode), -1};
    std::string link(static_cast<std::size_t>(st.st_size > 0 ? st.st_size : 4096) + 1, '\0');
    const ssize_t n = ::readlink(p.c_str(), link.data(), link.size());
    if (n < 0) fail(path, errno);
    link.resize(static_cast<std::size_t>(n));
    p = link.front() == '/' ? link : (fs::path(directory_of(p)) / link).string();
  }
  fail(path, ELOOP);
}

int claim_stdout() {
  std::lock_guard<std::mutex> lock(g_stdout_mutex);
  if (g_stdout_fd >= 0) return g_stdout_fd;
  std::fflush(stdout);
  g_stdout_fd = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
  if (g_stdout_fd >= 0) ::dup2(STDERR_FILENO, STDOUT_FILENO);  // our own text goes to stderr now
  return g_stdout_fd;
}

void protect_input(const std::string& path, const std::string& what) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  if (protected_input(st)) return;
  std::lock_guard<std::mutex> lock(g_inputs_mutex);
  g_inputs.push_back({st.st_dev, st.st_ino, what, path});
}

void set_no_clobber(bool on) { g_no_clobber = on; }
bool no_clobber() { return g_no_clobber; }
long committed_outputs() { return g_committed.load(std::memory_order_relaxed); }

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

OutputFile::OutputFile(std::string path, Replace replace) : path_(std::move(path)), replace_(replace) {
  if (path_.empty()) throw OutputFileError("cannot write an output with an empty path");
  const OutputTarget target = resolve_output(path_);
  target_ = target.path;
  if (target.streams) {
    open_stream(target.fd);
  } else {
    open_file();
  }
}

void OutputFile::open_stream(int inherited_fd) {
  streaming_ = true;
  if (inherited_fd < 0) {
    // No O_CREAT, no O_TRUNC: the device or FIFO is used as it is (a FIFO waits for a reader).
    fd_ = ::open(target_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
    if (fd_ < 0) fail(path_, errno);
    return;
  }
  const int source = inherited_fd == STDOUT_FILENO ? claim_stdout() : inherited_fd;
  const int flags = source >= 0 ? ::fcntl(source, F_GETFL) : -1;
  if (flags < 0) fail(path_, EBADF);  // no such descriptor open
  if ((flags & O_ACCMODE) == O_RDONLY) fail(path_, EBADF);
  fd_ = ::fcntl(source, F_DUPFD_CLOEXEC, 3);
  if (fd_ < 0) fail(path_, errno);
}

void OutputFile::open_file() {
  struct stat st {};
  if (::stat(target_.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) fail(path_, EISDIR);
    if (const auto in = protected_input(st))
      throw OutputFileError("cannot write " + path_ + ": it is " + in->what + " " + in->path +
                            (target_ == path_ ? "" : " (through a link)") +
                            ", and an output never replaces an input");
  }
  // 0666 less the umask, like any file the user makes (mkstemp's 0600 would surprise).
  fd_ = ::open(directory_of(target_).c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
  if (fd_ >= 0) return;
  if (!tmpfile_unsupported(errno)) fail(path_, errno);
  temp_ = hidden_temp_name(target_);
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
    stream_ = ::fdopen(fd_, streaming_ ? "wb" : "w+b");
    if (!stream_) fail(path_, errno);
  }
  return stream_;
}

std::string OutputFile::reopen_path() const {
  return temp_.empty() ? "/proc/self/fd/" + std::to_string(fd_) : temp_;
}

// The O_TMPFILE's name: linked straight onto a free name; over an existing file either
// through a hidden link renamed over it (kAtomic) or after removing it (kUnlinkFirst).
void OutputFile::link_into_place() {
  // linkat through /proc needs no privilege (AT_EMPTY_PATH would need CAP_DAC_READ_SEARCH).
  const std::string self = "/proc/self/fd/" + std::to_string(fd_);
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, target_.c_str(), AT_SYMLINK_FOLLOW) == 0) return;
    if (errno != EEXIST) fail(path_, errno);
    if (no_clobber()) fail_exists(path_);
    if (replace_ != Replace::kUnlinkFirst || attempt > 0) break;
    if (::unlink(target_.c_str()) != 0 && errno != ENOENT) break;  // then the rename says why
  }
  temp_ = hidden_temp_name(target_);
  if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temp_.c_str(), AT_SYMLINK_FOLLOW) != 0) {
    const int error = errno;
    temp_.clear();
    fail(path_, error);
  }
}

void OutputFile::commit() {
  if (committed_) return;
  try {
    if (stream_ && (std::fflush(stream_) != 0 || std::ferror(stream_))) fail(path_, errno ? errno : EIO);
    if (!streaming_ && temp_.empty()) link_into_place();
    if (!temp_.empty() && no_clobber()) {
      if (!rename_no_replace(temp_, target_)) errno == EEXIST ? fail_exists(path_) : fail(path_, errno);
    } else if (!temp_.empty() && std::rename(temp_.c_str(), target_.c_str()) != 0) {
      fail(path_, errno);
    }
  } catch (const OutputFileError&) {
    discard();
    throw;
  }
  temp_.clear();  // the data has its name now
  const int close_result = stream_ ? std::fclose(stream_) : ::close(fd_);
  const int error = errno;
  stream_ = nullptr;
  fd_ = -1;
  if (close_result != 0) {  // a network file system may report a failed write only here
    if (!streaming_) ::unlink(target_.c_str());
    fail(path_, error);
  }
  committed_ = true;
  ++g_committed;
}

}  // namespace clothsim
