#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <limits>

#include "cli_common.h"

namespace clothsim::clip {

namespace {
std::atomic<ProgressMode> g_mode{ProgressMode::automatic};
std::atomic<bool> g_quiet{false};
constexpr std::chrono::seconds kLinePeriod{5};  // often enough to see a job alive, rare enough for a log
}  // namespace

void set_progress_mode(ProgressMode mode) { g_mode = mode; }
void set_quiet(bool quiet) { g_quiet = quiet; }
bool quiet() { return g_quiet; }

Progress::Progress(std::string label, long total, std::string unit)
    : Progress(std::move(label), total, std::move(unit), g_mode, g_quiet, ::isatty(STDERR_FILENO) == 1, stderr,
               kLinePeriod) {}

Progress::Progress(std::string label, long total, std::string unit, ProgressMode mode, bool quiet, bool terminal,
                   std::FILE* out, std::chrono::milliseconds line_period)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), out_(out), period_(line_period),
      start_(std::chrono::steady_clock::now()), last_(start_ - std::chrono::seconds(1)) {
  if (quiet || mode == ProgressMode::never) style_ = Style::off;
  else if (terminal) style_ = Style::bar;
  else style_ = mode == ProgressMode::always ? Style::lines : Style::off;
  if (style_ == Style::lines) {  // a log shows that the work began, and how much there is
    line(0, 0.0, 0.0);
    last_ = start_;
  }
}

Progress::~Progress() { finish(); }

void Progress::finish() {
  if (style_ == Style::bar) std::fprintf(out_, "\r\033[K");
  style_ = Style::off;
}

double Progress::seconds_left(double elapsed, double share) {
  if (!(share > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return elapsed * std::max(0.0, 1.0 - share) / share;
}

void Progress::line(long done, double share, double elapsed) {
  std::fprintf(out_, "%s: %ld/%ld %s", label_.c_str(), done, total_, unit_.c_str());
  if (done >= total_) std::fprintf(out_, ", done in %.1f s\n", elapsed);
  else if (done > 0) std::fprintf(out_, ", %.1f s elapsed, %.1f s left\n", elapsed, seconds_left(elapsed, share));
  else std::fprintf(out_, "\n");
  std::fflush(out_);
}

void Progress::update(long done) {
  update(done, total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 0.0);
}

void Progress::update(long done, double share) {
  if (style_ == Style::off) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (style_ == Style::lines) {
    if (ended_ || (now - last_ < period_ && done < total_)) return;
    last_ = now;
    ended_ = done >= total_;
    line(done, share, elapsed);
    return;
  }
  if (now - last_ < std::chrono::milliseconds(100) && done < total_) return;
  last_ = now;
  std::fprintf(out_, "\r\033[K%s  %ld/%ld %s", label_.c_str(), done, total_, unit_.c_str());
  if (done > 0 && done < total_) std::fprintf(out_, "  %.1f s left", seconds_left(elapsed, share));
  std::fflush(out_);
}

}  // namespace clothsim::clip
