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
// What is not a regular file is written through, never replaced (docs/outputs.md): a
// character device (/dev/null), a FIFO or socket is opened and streamed; "-", /dev/stdout,
// /dev/stderr, /dev/fd/N and /proc/self/fd/N write into the descriptor the process holds; a
// symlink is followed, and the regular file it names is the one replaced.
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

// How an existing regular file under the name is replaced.
enum class Replace {
  kAtomic,       // renamed over: a reader sees old or new; a SIGKILL inside the rename's
                 // microseconds may leave the hidden link
  kUnlinkFirst,  // removed, then the new file linked: no hidden name ever exists, the name is
                 // briefly absent (a frame of a sequence being overwritten)
};

class OutputFile {
 public:
  // Creates the nameless (or hidden) file in the target's directory, or opens the device,
  // FIFO or descriptor to stream into. Throws OutputFileError.
  explicit OutputFile(std::string path, Replace replace = Replace::kAtomic);
  ~OutputFile();  // uncommitted: closed and, for a named temporary, removed
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Read and write for a file (libavformat's +faststart reads it back); write only when
  // streaming.
  int fd() const { return fd_; }
  std::FILE* stream();  // a stdio stream on fd(), made on first use
  // A name under which the data can be opened again by this process while writing:
  // /proc/self/fd/N, or the hidden temporary. libavformat reopens the file by name to move
  // the MP4 index to the front. Meaningless when streaming().
  std::string reopen_path() const;
  bool named_fallback() const { return !temp_.empty(); }
  // Written through to a device, FIFO, socket or inherited descriptor: no temporary, no
  // rename, not seekable in general, and what was written before an error stays written.
  bool streaming() const { return streaming_; }
  const std::string& path() const { return path_; }      // as the user gave it (messages)
  const std::string& target() const { return target_; }  // with its symlinks followed

  // Flushes, names the file `path` and closes it. Throws OutputFileError (a full disk often
  // shows only at the flush), after which nothing is under the name. With no_clobber(), a
  // name that exists by now is kept and the new file dropped (EEXIST), checked atomically.
  void commit();

 private:
  void open_stream(int inherited_fd);
  void open_file();
  void link_into_place();
  void discard();
  std::string path_, target_;
  std::string temp_;  // the named fallback's hidden temporary ("" with O_TMPFILE)
  Replace replace_;
  int fd_ = -1;
  std::FILE* stream_ = nullptr;
  bool streaming_ = false;
  bool committed_ = false;
};

// What an output path names: `path` with its symlinks followed (a regular file, a missing name,
// or a device), and whether writing there streams rather than replaces. "-", /dev/stdout and
// the descriptor paths stream into the process's own descriptor (`fd` >= 0).
struct OutputTarget {
  std::string path;
  bool streams = false;
  int fd = -1;
};
OutputTarget resolve_output(const std::string& path);  // throws OutputFileError (ELOOP...)

// An output streaming into standard output takes it: the command's own text (progress,
// "wrote ...") then goes to stderr, so a PNG piped to another program is not corrupted.
// Idempotent; returns the descriptor the data goes to.
int claim_stdout();

// Registers an input of the process (the scene, a golden, an encoded frame) by its device and
// inode: every OutputFile opened afterwards refuses to replace it, under any name, through a
// symlink or a hard link (a per-frame name made into a link to the scene, say). `what` names
// it in the message ("the scene"). A path that does not exist is ignored.
void protect_input(const std::string& path, const std::string& what);

// -n/--no-overwrite for every output of the process: commit() refuses a name that exists at
// that moment (linkat, renameat2 RENAME_NOREPLACE), so two -n runs cannot both win.
void set_no_clobber(bool on);
bool no_clobber();

// How many outputs this process has committed so far (async-signal-safe to read: a signal
// handler says whether anything stays).
long committed_outputs();

// A hidden, unique name beside `path` with the same extension (".clip.partial-PID-N.mp4"),
// for the named fallback.
std::string hidden_temp_name(const std::string& path);

// Writes `size` bytes at the descriptor's position, retrying short writes and EINTR.
// Returns false with errno set on failure.
bool write_all(int fd, const void* data, std::size_t size);

}  // namespace clothsim
