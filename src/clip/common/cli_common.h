// What every subcommand shares: exit codes, the two kinds of failure, files that appear
// whole or not at all, and progress (progress.h).
#pragma once

#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "scene/text.h"  // number_text, parse_number_or_fraction, split_list, trimmed
#include "progress.h"  // Progress, --progress, --quiet: every command uses them
#include "io/output_file.h"

namespace clothsim::clip {

// The CLI contract's exit codes (docs/outputs.md, "Exit codes").
// A run stopped by SIGINT, SIGTERM or SIGHUP exits 128 + the signal's number (130, 143, 129),
// as a shell reports a process killed by it, after cleaning up (main() maps it).
enum ExitCode : int { kOk = 0, kRuntimeFailure = 1, kBadInput = 2, kDiverged = 3, kNotConverged = 4, kWrong = 5 };
// The exit codes as --help lists them (clothsim --help, and run --help, which has its own footer).
inline constexpr const char* kExitCodesHelp =
    "Exit codes: 0 success, 1 runtime failure (I/O, GL, encoder), 2 bad usage or bad scene\n"
    "(also a run over --max-memory or past 1e9 steps / 1e7 frames), 3 the simulation diverged\n"
    "(run only), 4 a step did not converge (run --strict), 5 the run reads WRONG (run --strict),\n"
    "130 / 143 stopped by SIGINT (Ctrl-C) / SIGTERM, 129 by SIGHUP (at once, whatever the\n"
    "step; a second signal kills). What stays when: docs/outputs.md.\n";

// Bad usage or a bad scene: exit 2. The message is the whole one-line error.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// I/O, GL or encoder failure: exit 1.
struct RuntimeFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A CSV or JSON output: an OutputFile (io/output_file.h: nameless until commit(), so an
// error, a signal or even SIGKILL leaves nothing under the name) with RuntimeFailure errors.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path);  // throws RuntimeFailure if it cannot be created
  std::FILE* stream() { return file_->stream(); }
  const std::string& path() const { return file_->path(); }
  void commit();  // flush, name, close; throws RuntimeFailure "cannot write PATH: reason"
 private:
  std::unique_ptr<OutputFile> file_;
};

// A hidden temporary path beside `path` for files another process writes (the plot
// scripts), renamed by the caller. Throws RuntimeFailure if the directory does not exist
// or is not writable, naming the path.
std::string temp_path_beside(const std::string& path);
// Checks before any work is done that `path` can be created: its directory exists (made,
// with its parents, when missing) and is writable. Throws RuntimeFailure("cannot write OUT:
// cannot make its folder D: ..."), or with -n/--no-overwrite UsageError when `path` exists.
void require_writable_parent(const std::string& path, const std::string& what);
// A picture output (-o, --sheet) is PNG: a name whose extension says another format (x.jpg,
// y.gif) is refused (UsageError naming `what`) rather than given PNG bytes; no extension, or
// a stream (-, a device), is taken as it is.
void require_png_name(const std::string& path, const std::string& what);
// A path a command reads or writes, named by its option for messages ("--csv", "the scene").
// `frames_dir`: a directory of per-frame files (--frames, encode's inputs, an export's
// series), which claims the names it writes inside it or inside its lane folders (compare
// writes DIR/LANE/frame_*): frame_* when `prefixes` is empty, else PREFIX<digits>SUFFIX.
struct PathRole {
  std::string path;
  std::string what;
  bool frames_dir = false;
  std::vector<std::string> prefixes = {};
  std::string suffix = {};
};
// Refuses, before any work, an output that is one of the command's inputs or another of its
// outputs under any spelling (docs/outputs.md): the same device and inode where the file exists,
// the same path with symlinks (dangling ones too), `.` and `..` resolved where it does not; a
// frame_* file inside a frames directory of the command. A UsageError naming both. Empty
// paths and streams (devices, FIFOs, `-`, /dev/fd/N) are skipped: they are written through,
// never replaced, so several outputs may all be /dev/null. A name already in a frames
// directory that is a link (symbolic or hard) to an input is refused too, and every input is
// registered with protect_input(), so no writer of the process replaces it later either.
void refuse_clashing_paths(const std::vector<PathRole>& inputs, const std::vector<PathRole>& outputs);
// -n/--no-overwrite (ffmpeg's -n): an output that exists already is a UsageError (exit 2),
// raised by require_writable_parent() before any work; set by the option (progress.h).
bool no_overwrite();
void set_no_overwrite(bool on);
// With -n, a frames directory holding frame_* files is a UsageError too.
void refuse_existing_frames(const std::string& dir, const std::string& what);
// Creates `dir` (and parents) if missing; throws RuntimeFailure when impossible.
void ensure_directory(const std::string& dir, const std::string& what);


// What a stopped or failed command leaves: "kept A, B; not written: C" ("nothing kept").
std::string what_stays(const std::vector<std::string>& kept, const std::vector<std::string>& not_written);

// Signals (docs/outputs.md): SIGINT, SIGTERM and SIGHUP are answered by every command, with
// exit 128 + the signal's number (130, 143, 129) and one line saying what stays.
// install_signal_handlers() is main's first act. Until a command calls
// install_interrupt_handler(), a signal ends the process at once (nothing is being written
// then but nameless files); after it, the handler only records the signal, and the command's
// loops poll interrupted() and stop cleanly. A second signal ends the process at once.
void install_signal_handlers();
void install_interrupt_handler();  // "from here on this command polls interrupted()"
bool interrupted();
// A front end with signal handling of its own (Python's, whose Ctrl-C is a KeyboardInterrupt)
// asks the running work to stop as a signal would, and clears the request once it has.
void request_interrupt(int sig);
void clear_interrupt();
int interrupt_signal();                // 0: none
const char* interrupt_signal_name();  // "SIGINT", "SIGTERM", "SIGHUP"
// Throws the RuntimeFailure "stopped by SIGINT WHILE; nothing written" when a signal has
// arrived: for the phases before a command writes anything (planning, pilot runs).
void stop_if_interrupted(const std::string& phase);
// What main returns for a command that ended with `code`: 128 + the signal when one arrived
// after the command's last poll (saying so on stderr), so no signal is lost.
int exit_code_after(int code);
// The one line a stopped command ends with (main adds "clothsim: "), saying exactly what stays
// on disk and what does not: "stopped by SIGTERM at t = 0.2 s; kept 7 PNGs in out/; not
// written: m.csv, clip.mp4" ("nothing kept" when `kept` is empty).
std::string interruption_message(double t, const std::vector<std::string>& kept,
                                 const std::vector<std::string>& not_written);



}  // namespace clothsim::clip
