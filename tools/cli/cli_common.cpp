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
  static std::atomic<int> counter{0};
  const fs::path p(path);
  // Hidden, unique, and with the same extension (libavformat picks the container from it).
  const std::string name = "." + p.stem().string() + ".partial-" + std::to_string(::getpid()) + "-" +
                           std::to_string(counter++) + p.extension().string();
  return (p.has_parent_path() ? p.parent_path() / name : fs::path(name)).string();
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

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temp_(temp_path_beside(path_)) {
  stream_ = std::fopen(temp_.c_str(), "wb");
  if (!stream_) throw RuntimeFailure("cannot write " + path_ + ": " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (stream_) std::fclose(stream_);
  if (!committed_) std::remove(temp_.c_str());
}

void AtomicFile::commit() {
  const bool write_ok = std::fflush(stream_) == 0 && !std::ferror(stream_);
  const bool close_ok = std::fclose(stream_) == 0;
  stream_ = nullptr;
  if (!write_ok || !close_ok) throw RuntimeFailure("cannot write " + path_ + ": " + std::strerror(errno));
  if (std::rename(temp_.c_str(), path_.c_str()) != 0)
    throw RuntimeFailure("cannot rename " + temp_ + " to " + path_ + ": " + std::strerror(errno));
  committed_ = true;
}

namespace {
std::atomic<int> g_signal{0};  // lock-free, so safe to store from a handler
extern "C" void on_sigint(int sig) {
  g_signal.store(sig);
  std::signal(sig, SIG_DFL);  // a second Ctrl-C (or TERM) kills at once
}
}  // namespace

bool interrupted() { return g_signal.load(std::memory_order_relaxed) != 0; }
int interrupt_signal() { return g_signal.load(std::memory_order_relaxed); }

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
