// Progress of long work on stderr, and the options that say how much of it to show:
//   --progress auto    a bar redrawn in place when stderr is a terminal, nothing otherwise (default)
//   --progress always  the bar on a terminal; otherwise one plain line about every 5 s, plus one
//                      at the start and one at the end, for logs (nohup, Slurm, CI), as
//                      ffmpeg's -stats_period does
//   --progress never   nothing
//   --quiet            nothing on stderr but errors and warnings (no progress, no timings);
//                      the results on stdout stay
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace clothsim::clip {

enum class ProgressMode { automatic, always, never };

void set_progress_mode(ProgressMode mode);
void set_quiet(bool quiet);
bool quiet();  // --quiet: commands skip their informational stderr lines

// "label  37/150 frames  1.2 s left" redrawn at most 10 times a second on a terminal, or
// "label: 37/150 frames, 5.0 s elapsed, 15.2 s left" lines for a log, as the settings say.
class Progress {
 public:
  Progress(std::string label, long total, std::string unit);
  // Explicitly (tests): the mode, whether `out` is a terminal, and the plain lines' period.
  Progress(std::string label, long total, std::string unit, ProgressMode mode, bool quiet, bool terminal,
           std::FILE* out, std::chrono::milliseconds line_period);
  ~Progress();  // clears the bar (as finish() does)
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void update(long done);
  // The same with the share of the work done (0 to 1) where units of work weigh unlike (a study's
  // runs: analysis::StudyProgress): the time left is the time so far x (1 - share) / share.
  void update(long done, double share);
  void finish();  // clears the bar now, before a summary is printed; idempotent
  // Seconds left after `elapsed` s with `share` of the work done (NaN before any is done).
  static double seconds_left(double elapsed, double share);
 private:
  enum class Style { off, bar, lines };
  void line(long done, double share, double elapsed);
  std::string label_, unit_;
  long total_;
  Style style_;
  std::FILE* out_;
  std::chrono::milliseconds period_;
  std::chrono::steady_clock::time_point start_, last_;
  bool ended_ = false;  // the closing line has been written (lines style)
};

}  // namespace clothsim::clip
