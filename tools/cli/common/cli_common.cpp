#include "cli_common.h"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <unistd.h>

namespace clothsim::cli {
namespace fs = std::filesystem;

namespace {
std::string parent_of(const std::string& path) {
  const fs::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : std::string(".");
}
}  // namespace

void require_writable_parent(const std::string& path, const std::string& what) {
  if (path.empty()) throw RuntimeFailure(what + ": empty output path");
  const std::string dir = parent_of(path);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw RuntimeFailure("cannot write " + what + " " + path + ": directory " + dir + " does not exist");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw RuntimeFailure("cannot write " + what + " " + path + ": directory " + dir + " is not writable");
  if (fs::is_directory(path, ec))
    throw RuntimeFailure("cannot write " + what + " " + path + ": it is a directory");
  if (no_overwrite() && fs::exists(path, ec))
    throw UsageError(what + ": " + path + " exists, and -n/--no-overwrite keeps it");
}

void refuse_shared_outputs(const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::vector<std::pair<fs::path, std::string>> seen;
  for (const auto& [path, what] : outputs) {
    if (path.empty()) continue;
    std::error_code ec;
    fs::path resolved = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec) resolved = fs::absolute(path).lexically_normal();
    for (const auto& [other, other_what] : seen)
      if (other == resolved)
        throw UsageError(what + " and " + other_what + " both write " + path + ": give each its own path");
    seen.emplace_back(resolved, what);
  }
}

namespace {
std::atomic<bool> g_no_overwrite{false};
}  // namespace

bool no_overwrite() { return g_no_overwrite; }
void set_no_overwrite(bool on) { g_no_overwrite = on; }

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
std::atomic<int> g_signal{0};  // lock-free, so safe to store from a handler
extern "C" void on_sigint(int sig) {
  // A second signal of either kind kills at once (a batch scheduler's TERM after a Ctrl-C,
  // or a user's second Ctrl-C while cleanup is stuck): the handler is removed by the first,
  // and a second that reaches another thread's handler before that (both arrived together;
  // the suite's test does exactly this) finds the first recorded and kills by itself.
  // signal() and raise() are async-signal-safe.
  int none = 0;
  const bool first = g_signal.compare_exchange_strong(none, sig);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (!first) std::raise(sig);  // delivered, with the default action, as the handler returns
}
}  // namespace

bool interrupted() { return g_signal.load(std::memory_order_relaxed) != 0; }
int interrupt_signal() { return g_signal.load(std::memory_order_relaxed); }

const char* interrupt_signal_name() {
  const int sig = interrupt_signal();
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
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

std::string interruption_message(double t, const std::vector<std::string>& kept,
                                 const std::vector<std::string>& not_written) {
  char when[64];
  std::snprintf(when, sizeof when, "%.6g", t);
  return std::string("stopped by ") + interrupt_signal_name() + " at t = " + when + " s; " + what_stays(kept, not_written);
}

void install_interrupt_handler() {
  struct sigaction sa{};
  sa.sa_handler = on_sigint;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

std::optional<double> parse_number_or_fraction(const std::string& text) {
  const auto number = [](const std::string& s) -> std::optional<double> {
    if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (*end != '\0' || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    return v;
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) return number(text);
  const auto num = number(text.substr(0, slash)), den = number(text.substr(slash + 1));
  if (!num || !den || *den == 0.0 || !std::isfinite(*num / *den)) return std::nullopt;
  return *num / *den;
}

std::vector<std::string> split_list(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!text.empty() && text.back() == sep) out.emplace_back();
  return out;
}

}  // namespace clothsim::cli
