#include "memory_budget.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "cli_common.h"
#include "cli/compare/reference_stand.h"
#include "scene/echo.h"
#include "scene/parse_estimate.h"
#include "scene/scene_parser.h"

namespace clothsim::cli {

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
  return (20.0 + 8.0 * std::min(samples, 4)) * width * height;  // llvmpipe caps MSAA at 4 here
}

double held_frames_bytes(const SceneDef& scene, std::size_t lanes, double frames) {
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  return 96.0 * particles * static_cast<double>(lanes) * frames;
}

double reference_positions_bytes(const SceneDef& scene, const std::vector<double>& lane_steps,
                                 const TargetPlan& plan, std::size_t queue) {
  std::vector<double> distinct;
  for (double h : lane_steps)
    if (std::find(distinct.begin(), distinct.end(), h) == distinct.end()) distinct.push_back(h);
  const double copies = static_cast<double>(ReferenceStand::waiting_bound(lane_steps, plan)) +
                        static_cast<double>(queue) + 2.0;
  const double particles = static_cast<double>(scene.cloth.nx) * scene.cloth.ny;
  return 24.0 * particles * (4.0 + copies * static_cast<double>(distinct.size()));
}

double encoder_bytes(int width, int height) { return 64.0 * (width + (width & 1)) * (height + (height & 1)); }

void add_max_memory_option(CLI::App* sub, std::optional<double>& limit) {
  sub->add_option_function<std::string>(
         "--max-memory",
         [&limit](const std::string& text) {
           limit = parse_memory_size(text);
           if (!limit)
             throw CLI::ValidationError("--max-memory: " + in_quotes(text) + " is not a size (e.g. 4G, 512M, 1.5G)");
         },
         "Refuse (exit 2, with the estimate) a run whose estimated peak memory exceeds SIZE "
         "(4G, 512M; default: half the physical memory)")
      ->type_name("SIZE");
}

MemoryBudget::MemoryBudget() { add("process", kProcessBytes); }

double MemoryBudget::total() const {
  double sum = 0.0;
  for (const auto& part : parts_) sum += part.second;
  return sum;
}

void MemoryBudget::check(const std::string& source, const std::optional<double>& limit) const {
  const double allowed = limit ? *limit : default_memory_limit();
  const double needed = total();
  if (needed <= allowed) return;
  std::string parts;
  for (const auto& [what, bytes] : parts_) parts += (parts.empty() ? "" : ", ") + what + " " + format_bytes(bytes);
  throw UsageError(source + ": needs an estimated " + format_bytes(needed) + " (" + parts + "), more than " +
                   (limit ? "--max-memory " + format_bytes(allowed)
                          : "the " + format_bytes(allowed) + " allowed by default (half the physical memory)") +
                   "; " + remedy_ + ", or raise --max-memory");
}

void check_parse_budget(const std::string& path, const std::optional<double>& limit) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  const YamlSize size = count_yaml_nodes(in);
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

SceneDef load_scene_within(const std::string& path, const std::vector<std::string>& overrides,
                           const std::optional<double>& limit) {
  check_parse_budget(path, limit);
  return load_scene(path, overrides);
}

}  // namespace clothsim::cli
