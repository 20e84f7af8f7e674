#include "memory_budget.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli_common.h"
#include "scene/echo.h"
#include "scene/parse_estimate.h"
#include "scene/scene_parser.h"

namespace clothsim::clip {

std::optional<double> parse_memory_size(const std::string& text) {
  if (text.empty() || !(std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '.')) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double number = std::strtod(text.c_str(), &end);
  if (errno == ERANGE || !std::isfinite(number) || number <= 0.0) return std::nullopt;
  std::string unit(end);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() > 1 && (unit.back() == 'B')) unit.pop_back();  // "800MB", "4GB"
  if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();         // "4GiB"
  double scale = 1.0;
  if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!unit.empty() && unit != "B") return std::nullopt;
  return number * scale;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1024.0 && u < 5) {
    bytes /= 1024.0;
    ++u;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %s", bytes, units[u]);  // 3 digits: 2.04 GB is over 2 GB
  return text;
}

double default_memory_limit() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return 4.0 * 1024 * 1024 * 1024;  // unknown: a modest machine's half
  return 0.5 * static_cast<double>(pages) * static_cast<double>(page);
}

double render_bytes(int width, int height, int samples) {
  return (4.0 + 11.0 * std::min(samples, 4)) * width * height;  // llvmpipe caps MSAA at 4 here
}

double held_frames_bytes(const SceneDef& scene, std::size_t lanes, double frames) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  return 96.0 * particles * static_cast<double>(lanes) * frames;
}

double export_bytes(const SceneDef& scene, ExportFormat format) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  return (format == ExportFormat::Pvd ? 600.0 : 360.0) * particles;
}

double encoder_bytes(int width, int height) {
  return 24.0 * 1024 * 1024 + 116.0 * (width + (width & 1)) * (height + (height & 1));
}

double max_memory_option(const std::string& text) {
  const std::optional<double> limit = parse_memory_size(text);
  if (!limit) throw UsageError("--max-memory: " + in_quotes(text) + " is not a size (e.g. 4G, 512M, 1.5G)");
  return *limit;
}

MemoryBudget::MemoryBudget() { add("process", kProcessBytes); }

double MemoryBudget::total() const {
  double sum = 0.0;
  for (const auto& part : parts_) sum += part.second;
  return sum;
}

std::optional<double> address_space_limit() {
  rlimit rl {};
  if (::getrlimit(RLIMIT_AS, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return std::nullopt;
  return static_cast<double>(rl.rlim_cur);
}

double address_space_mapped() {
  std::ifstream statm("/proc/self/statm");
  double pages = 0.0;
  statm >> pages;  // the first field: every page mapped, touched or not
  return pages * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
}

void MemoryBudget::check(const std::string& source, const std::optional<double>& limit) const {
  const double allowed = limit ? *limit : default_memory_limit();
  const double needed = total();
  std::string parts;
  for (const auto& [what, bytes] : parts_) parts += (parts.empty() ? "" : ", ") + what + " " + format_bytes(bytes);
  if (needed > allowed)
    throw UsageError(source + ": needs an estimated " + format_bytes(needed) + " (" + parts + "), more than " +
                     (limit ? "--max-memory " + format_bytes(allowed)
                            : "the " + format_bytes(allowed) + " allowed by default (half the physical memory)") +
                     "; " + remedy_ + ", or raise --max-memory");
  // Under ulimit -v, what is still to be mapped (the estimate beyond the process already
  // running, and the threads' stacks and malloc arenas) must fit what the limit leaves.
  const std::optional<double> as_limit = address_space_limit();
  if (!as_limit) return;
  const double mapped = address_space_mapped();
  if (needed - kProcessBytes + kAddressSpaceReserve <= *as_limit - mapped) return;
  // The machine's limit, not the scene's fault: exit 1, as the renderer's own check of it says.
  throw RuntimeFailure(source + ": needs an estimated " + format_bytes(needed) + " (" + parts + "), more than the " +
                   "address-space limit (ulimit -v " + format_bytes(*as_limit) + ", " + format_bytes(mapped) +
                   " of it mapped already) leaves; " + remedy_ + ", or raise ulimit -v");
}

namespace {
// Refuses a YAML text whose tree would pass `limit` (see check_parse_budget).
void check_tree_budget(const std::string& path, const YamlSize& size, const std::optional<double>& limit) {
  // A scene of a few thousand nodes is part of the process's allowance (kProcessBytes), so
  // only a large file is judged on its parse; the run's own estimate judges the rest.
  if (parse_bytes(size) <= kSmallSceneTreeBytes) return;
  MemoryBudget budget;
  budget.add("YAML tree (" + std::to_string(size.nodes) + " nodes, " + format_bytes(static_cast<double>(size.bytes)) +
                 " of text)",
             parse_bytes(size));
  budget.set_remedy("shorten the scene file (its keyframes, pins and lists)");
  budget.check(path, limit);
}

[[noreturn]] void stream_failure(const std::string& path, int error) {
  if (interrupted()) stop_if_interrupted("while reading " + path);  // a FIFO with no writer yet
  throw SceneError(path, 0, "", std::string("cannot read: ") + std::strerror(error));
}
}  // namespace

void check_parse_budget(const std::string& path, const std::optional<double>& limit) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  check_tree_budget(path, count_yaml_nodes(in), limit);
}

std::optional<std::string> read_scene_stream(const std::string& path, const std::optional<double>& limit) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) return std::nullopt;
  // A tree costs several times its text (parse_estimate.h), so a text of more than a quarter
  // of the limit cannot be parsed within it: reading stops there.
  const double cap = 0.25 * (limit ? *limit : default_memory_limit());
  int fd = -1;
  while ((fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC)) < 0)  // a FIFO waits for its writer
    if (errno != EINTR || interrupted()) stream_failure(path, errno);
  std::string text;
  char chunk[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, chunk, sizeof chunk);
    if (n == 0) break;
    if (n < 0) {
      if (errno == EINTR && !interrupted()) continue;
      const int error = errno;
      ::close(fd);
      stream_failure(path, error);
    }
    text.append(chunk, static_cast<std::size_t>(n));
    if (static_cast<double>(text.size()) > cap) {
      ::close(fd);
      throw UsageError(path + ": more than " + format_bytes(cap) + " read from this stream and more coming; a scene's "
                       "text must stay within a quarter of " + (limit ? "--max-memory " + format_bytes(*limit)
                                                                      : "the memory allowed by default") +
                       " (its parse needs several times that)");
    }
  }
  ::close(fd);
  std::istringstream in(text);
  check_tree_budget(path, count_yaml_nodes(in), limit);
  return text;
}

SceneDef load_scene_within(const std::string& path, const std::vector<std::string>& overrides,
                           const std::optional<double>& limit, bool bound_run) {
  if (const std::optional<std::string> text = read_scene_stream(path, limit))
    return parse_scene(*text, path, overrides, bound_run);
  check_parse_budget(path, limit);
  return load_scene(path, overrides, bound_run);
}

}  // namespace clothsim::clip
