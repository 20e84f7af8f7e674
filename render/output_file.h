// OutputFile: every file clothsim writes (PNG, MP4, CSV, JSON) appears under its name only
// when complete, and nothing is left behind otherwise, not even after SIGKILL.
//
// How: Linux's open(dir, O_TMPFILE) creates a file with no name in the target's directory;
// commit() gives it the name with linkat() through /proc/self/fd (straight onto the name when
// it is free, else onto a hidden name renamed over the old file, so a reader sees the old or
// the new file, never a mix). A process killed before commit() leaves an unnamed inode that
// the kernel frees with the descriptor. Where the file system lacks O_TMPFILE (EOPNOTSUPP,
// EISDIR on old kernels, some network and FUSE mounts), a hidden named temporary beside the
// target is used instead: removed on every error, signal and exception, but left by SIGKILL.
//
// It lives in render/ because it is the lowest library every writer links (png_io here, the
// video writer, the CLI's CSV and JSON); it is plain POSIX and knows nothing of images.
#pragma once

#include <cstdio>
#include <stdexcept>
#include <string>

namespace clothsim {

// "cannot write PATH: strerror text" (one line).
struct OutputFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class OutputFile {
 public:
  // Creates the nameless (or hidden) file in `path`'s directory. Throws OutputFileError.
  explicit OutputFile(std::string path);
  ~OutputFile();  // uncommitted: closed and, for a named temporary, removed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  int fd() const { return fd_; }  // read and write (libavformat's +faststart reads it back)
  std::FILE* stream();            // a stdio stream on fd(), made on first use
  // A name under which the data can be opened again by this process while writing:
  // /proc/self/fd/N, or the hidden temporary. libavformat reopens the file by name to move
  // the MP4 index to the front.
  std::string reopen_path() const;
  bool named_fallback() const { return !temp_.empty(); }
  const std::string& path() const { return path_; }

  // Flushes, names the file `path` and closes it. Throws OutputFileError (a full disk often
  // shows only at the flush), after which nothing is under the name.
  void commit();

 private:
  void discard();
  std::string path_;
  std::string temp_;  // the named fallback's hidden temporary ("" with O_TMPFILE)
  int fd_ = -1;
  std::FILE* stream_ = nullptr;
  bool committed_ = false;
};

// A hidden, unique name beside `path` with the same extension (".clip.partial-PID-N.mp4"),
// for the named fallback and for files other processes write (the plot scripts).
std::string hidden_temp_name(const std::string& path);

// Writes `size` bytes at the descriptor's position, retrying short writes and EINTR.
// Returns false with errno set on failure.
bool write_all(int fd, const void* data, std::size_t size);

}  // namespace clothsim
