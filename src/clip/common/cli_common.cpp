#include "cli_common.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

#include "scene/echo.h"

namespace clothsim::clip {
namespace fs = std::filesystem;

namespace {
std::string parent_of(const std::string& path) {
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}
}  // namespace

void require_png_name(const std::string& path, const std::string& what) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext.empty() || ext == ".png") return;
  throw UsageError(what + ": " + in_quotes(path) + " names a " + ext.substr(1) +
                   " file, and clothsim writes PNG only; give a .png name");
}

void require_writable_parent(const std::string& path, const std::string& what) {
  if (path.empty()) throw RuntimeFailure(what + ": empty output path");
  OutputTarget target;
  try {
    target = resolve_output(path);
  } catch (const OutputFileError& e) {
    throw RuntimeFailure(e.what());
  }
  if (target.streams) {  // a device, FIFO or descriptor is written through: no directory entry is made
    if (target.fd == STDOUT_FILENO) claim_stdout();  // before any "wrote ..." reaches it
    return;
  }
  const std::string dir = parent_of(target.path);
  std::error_code ec;
  // One rule for every output, as --frames has it: missing folders are made (docs/cli.md).
  if (!fs::is_directory(dir, ec) && !fs::create_directories(dir, ec) && !fs::is_directory(dir))
    throw RuntimeFailure("cannot write " + what + " " + path + ": cannot make its folder " + dir +
                         (ec ? ": " + ec.message() : ""));
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw RuntimeFailure("cannot write " + what + " " + path + ": directory " + dir + " is not writable");
  if (fs::is_directory(target.path, ec))
    throw RuntimeFailure("cannot write " + what + " " + path + ": it is a directory");
  if (no_overwrite() && fs::exists(target.path, ec))
    throw UsageError(what + ": " + path + " exists, and -n/--no-overwrite keeps it");
}

namespace {
// What a path names, for telling two spellings of one file apart.
struct PathIdentity {
  bool stream = false;  // a device, FIFO or descriptor: written through, never replaced
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
  fs::path resolved;  // absolute, symlinks followed: the identity of a name not made yet
};

fs::path resolved_path(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : p;
}

PathIdentity identify(const std::string& path) {
  PathIdentity id;
  OutputTarget target{path, false, -1};
  try {
    target = resolve_output(path);  // follows symlinks, dangling ones too
  } catch (const OutputFileError&) {  // a loop: said by the writer; compared by its spelling here
  }
  if (target.streams) {
    id.stream = true;
    return id;
  }
  struct stat st {};
  if (::stat(target.path.c_str(), &st) == 0) {
    id.exists = true;
    id.dev = st.st_dev;
    id.ino = st.st_ino;
  }
  id.resolved = resolved_path(target.path);
  return id;
}

bool same_file(const PathIdentity& a, const PathIdentity& b) {
  if (a.exists != b.exists) return false;
  return a.exists ? a.dev == b.dev && a.ino == b.ino : a.resolved == b.resolved;
}

bool claims_name(const PathRole& dir, const std::string& name) {
  if (dir.prefixes.empty()) return name.rfind("frame_", 0) == 0;
  const std::string& sfx = dir.suffix;
  for (const std::string& prefix : dir.prefixes) {
    if (name.size() <= prefix.size() + sfx.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - sfx.size(), sfx.size(), sfx) != 0)
      continue;
    const auto first = name.begin() + static_cast<long>(prefix.size());
    const auto last = name.end() - static_cast<long>(sfx.size());
    if (std::all_of(first, last, [](char c) { return c >= '0' && c <= '9'; })) return true;
  }
  return false;
}

// A file the frames directory `dir` claims: directly inside it, or in one of its lane folders.
bool claimed_by_frames_dir(const PathIdentity& file, const PathIdentity& dir, const PathRole& role) {
  if (!claims_name(role, file.resolved.filename().string())) return false;
  const fs::path parent = file.resolved.parent_path();
  return same_file(identify(parent.string()), dir) || same_file(identify(parent.parent_path().string()), dir);
}

// The names a frames directory claims that exist already as links (symbolic, or hard: more
// than one name), in it and in its lane folders: what a run would write through.
std::vector<fs::path> linked_frames(const PathRole& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  const auto scan = [&](const fs::path& folder, auto& self, int depth) -> void {
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      const std::string name = entry.path().filename().string();
      std::error_code e;
      if (entry.is_symlink(e) || (entry.is_regular_file(e) && entry.hard_link_count(e) > 1)) {
        if (claims_name(dir, name)) out.push_back(entry.path());
      } else if (depth == 0 && entry.is_directory(e)) {
        self(entry.path(), self, 1);
      }
    }
  };
  if (fs::is_directory(dir.path, ec)) scan(dir.path, scan, 0);
  return out;
}
}  // namespace

void refuse_clashing_paths(const std::vector<PathRole>& inputs, const std::vector<PathRole>& outputs) {
  struct Seen {
    const PathRole* role;
    PathIdentity id;
    bool input;
  };
  std::vector<Seen> seen;
  for (const PathRole& in : inputs) {
    if (in.path.empty()) continue;
    seen.push_back({&in, identify(in.path), true});
    protect_input(in.path, in.what);
  }
  for (const PathRole& out : outputs) {
    if (out.path.empty()) continue;
    const PathIdentity id = identify(out.path);
    if (id.stream) continue;  // --metrics /dev/null --state /dev/null
    if (out.frames_dir)
      for (const fs::path& link : linked_frames(out)) {
        const PathIdentity target = identify(link.string());
        for (const Seen& other : seen)
          if (other.input && !other.id.stream && same_file(target, other.id))
            throw UsageError(out.what + " " + out.path + " would write through " + link.string() + ", a link to " +
                             other.role->what + " " + other.role->path +
                             ": an output never replaces an input; remove the link or give the output its own folder");
      }
    for (const Seen& other : seen) {
      if (other.id.stream) continue;
      const PathRole& o = *other.role;
      const std::string them = o.what + " " + o.path;
      if (same_file(id, other.id)) {
        if (other.input)
          throw UsageError(out.what + " " + out.path + " is " + them + (out.path == o.path ? "" : " under another name") +
                           ": an output never replaces an input; give it its own path");
        throw UsageError(out.what + " and " + o.what + " both write " + out.path +
                         (out.path == o.path ? "" : " (as " + o.path + ")") + ": give each its own path");
      }
      if (o.frames_dir && !out.frames_dir && claimed_by_frames_dir(id, other.id, o))
        throw UsageError(out.what + " " + out.path + " is a frame of " + them +
                         (other.input ? ": an output never replaces an input; give it its own path"
                                      : ", which writes it too: give each its own path"));
      if (out.frames_dir && !o.frames_dir && claimed_by_frames_dir(other.id, id, out))
        throw UsageError(out.what + " " + out.path + " would write frames over " + them +
                         (other.input ? ": an output never replaces an input; give it its own path"
                                      : ": give each its own path"));
    }
    seen.push_back({&out, id, false});
  }
}

namespace {
std::atomic<bool> g_no_overwrite{false};
}  // namespace

bool no_overwrite() { return g_no_overwrite; }
void set_no_overwrite(bool on) {
  g_no_overwrite = on;
  set_no_clobber(on);  // and checked again, atomically, as each file is named
}

void refuse_existing_frames(const std::string& dir, const std::string& what) {
  if (!no_overwrite()) return;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().filename().string().rfind("frame_", 0) == 0)
      throw UsageError(what + ": " + dir + " already holds frames (" + entry.path().filename().string() +
                       "), and -n/--no-overwrite keeps them");
}

std::string temp_path_beside(const std::string& path) {
  require_writable_parent(path, "output");
  return hidden_temp_name(path);
}

void ensure_directory(const std::string& dir, const std::string& what) {
  std::error_code ec;
  if (fs::is_directory(dir, ec)) {
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw RuntimeFailure("cannot write " + what + " into " + dir + ": directory is not writable");
    return;
  }
  if (fs::exists(dir, ec)) throw RuntimeFailure("cannot write " + what + " into " + dir + ": not a directory");
  fs::create_directories(dir, ec);
  if (ec) throw RuntimeFailure("cannot create " + what + " directory " + dir + ": " + ec.message());
}

AtomicFile::AtomicFile(const std::string& path) {
  try {
    file_ = std::make_unique<OutputFile>(path);
  } catch (const OutputFileError& e) {
    throw RuntimeFailure(e.what());
  }
}

void AtomicFile::commit() {
  try {
    file_->commit();
  } catch (const OutputFileError& e) {
    throw RuntimeFailure(e.what());
  }
}

namespace {
std::atomic<int> g_signal{0};       // lock-free, so safe to store from a handler
std::atomic<bool> g_polling{false};  // the command polls interrupted() (install_interrupt_handler)
constexpr int kAnsweredSignals[] = {SIGINT, SIGTERM, SIGHUP};

const char* signal_name(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
}

void write_text(const char* text) {
  for (std::size_t left = std::strlen(text); left > 0;) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<std::size_t>(n);
  }
}

// A signal before the command polls for one (parsing, loading, a command with nothing long to
// stop): nothing of it is worth finishing, so the process ends here, saying what stays. The
// outputs still being written are nameless (OutputFile) and vanish with the process.
[[noreturn]] void stop_at_once(int sig) {
  write_text("clothsim: stopped by ");
  write_text(signal_name(sig));
  write_text(committed_outputs() == 0 ? "; nothing written\n" : "; the files already written stay, nothing else\n");
  ::_exit(128 + sig);
}

extern "C" void on_signal(int sig) {
  // A second signal of any of the three kills at once (a batch scheduler's TERM after a
  // Ctrl-C, or a user's second Ctrl-C while cleanup is stuck): the handler is removed by the
  // first, and a second that reaches another thread's handler before that (both arrived
  // together; the suite's test does exactly this) finds the first recorded and kills by itself.
  // signal(), raise(), write() and _exit() are async-signal-safe.
  int none = 0;
  const bool first = g_signal.compare_exchange_strong(none, sig);
  for (const int s : kAnsweredSignals) std::signal(s, SIG_DFL);
  if (!first) {
    std::raise(sig);  // delivered, with the default action, as the handler returns
    return;
  }
  if (!g_polling.load()) stop_at_once(sig);
}
}  // namespace

bool interrupted() { return g_signal.load(std::memory_order_relaxed) != 0; }
int interrupt_signal() { return g_signal.load(std::memory_order_relaxed); }
void request_interrupt(int sig) {
  int none = 0;
  g_signal.compare_exchange_strong(none, sig);
}
void clear_interrupt() { g_signal.store(0); }
const char* interrupt_signal_name() { return signal_name(interrupt_signal()); }

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (const int s : kAnsweredSignals) sigaddset(&sa.sa_mask, s);  // one handler at a time
  for (const int s : kAnsweredSignals) {
    struct sigaction inherited {};
    // Ignored on entry (nohup's SIGHUP) stays ignored, as a shell's trap leaves it.
    if (sigaction(s, nullptr, &inherited) == 0 && inherited.sa_handler == SIG_IGN) continue;
    sigaction(s, &sa, nullptr);
  }
  // The launcher (launcher.cpp) holds the three blocked through the dynamic loader's work; a
  // signal pending since then is answered here, by the handler just installed.
  sigprocmask(SIG_UNBLOCK, &sa.sa_mask, nullptr);
  // A reader that goes away (`-o - | head -c 100`) makes the write fail with EPIPE, reported
  // on one line like any write error, instead of killing the process without a word.
  std::signal(SIGPIPE, SIG_IGN);
}

void install_interrupt_handler() { g_polling = true; }

int exit_code_after(int code) {
  g_polling = false;  // from here (libraries' teardown) a signal ends the process at once
  if (!interrupted()) return code;
  // The work was done when the signal was seen (after the last poll): every output stands.
  std::fprintf(stderr, "clothsim: stopped by %s after the work was done; every output is written\n",
               interrupt_signal_name());
  return 128 + interrupt_signal();
}

std::string what_stays(const std::vector<std::string>& kept, const std::vector<std::string>& not_written) {
  const auto join = [](const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
  };
  std::string out = kept.empty() ? "nothing kept" : "kept " + join(kept);
  if (!not_written.empty()) out += "; not written: " + join(not_written);
  return out;
}

void stop_if_interrupted(const std::string& phase) {
  if (interrupted()) throw RuntimeFailure(std::string("stopped by ") + interrupt_signal_name() + " " + phase + "; nothing written");
}

std::string interruption_message(double t, const std::vector<std::string>& kept,
                                 const std::vector<std::string>& not_written) {
  char when[64];
  std::snprintf(when, sizeof when, "%.6g", t);
  return std::string("stopped by ") + interrupt_signal_name() + " at t = " + when + " s; " + what_stays(kept, not_written);
}

}  // namespace clothsim::clip
