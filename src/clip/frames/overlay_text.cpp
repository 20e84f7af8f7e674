#include "overlay_text.h"

#include "clip/common/lanes.h"  // integrator_label
#include "core/integrators/integrator_kind.h"

#include <cmath>
#include <cstdio>

namespace clothsim::clip {

std::vector<std::string> overlay_lines(const Model& model, const std::string& lane_label, double t) {
  return {model.name, lane_label, overlay_time_line(t)};
}

std::vector<std::string> overlay_lines(const Model& model, IntegratorKind kind, double dt, double t) {
  char step[32];
  std::snprintf(step, sizeof step, "%.3g", dt);
  return overlay_lines(model, integrator_label(method_name(kind, model.implicit), step), t);
}

std::string overlay_time_line(double t) {
  char line[48];
  std::snprintf(line, sizeof line, "t = %.3f s", t);
  return line;
}

namespace {
// The time as `run` prints it (%.6g), and the step: the picture and the exit message agree.
std::string diverged_time(const Divergence& divergence) {
  char time[48];
  std::snprintf(time, sizeof time, "at t = %.6g s", divergence.t);
  return time;
}
}  // namespace

void mark_diverged(RenderFrame& frame, const Divergence& divergence, double predicted_limit) {
  frame.banner = {"DIVERGED", diverged_time(divergence), "(step " + std::to_string(divergence.step) + ")"};
  frame.overlay_lines.push_back("diverged: " + divergence.reason);
  if (const std::string stable = stable_step_line(predicted_limit); !stable.empty()) frame.overlay_lines.push_back(stable);
}

std::string stable_step_line(double predicted_limit) {
  if (std::isnan(predicted_limit) || std::isinf(predicted_limit)) return "";
  if (!(predicted_limit > 0.0)) return "no stable step (estimate)";
  char line[64];
  std::snprintf(line, sizeof line, "stable below ~%.2g s (estimate)", predicted_limit);
  return line;
}

std::vector<std::string> diverged_caption(const Divergence& divergence, double predicted_limit) {
  std::vector<std::string> lines{"DIVERGED " + diverged_time(divergence) + " (step " + std::to_string(divergence.step) + ")",
                                 divergence.reason};
  if (const std::string stable = stable_step_line(predicted_limit); !stable.empty()) lines.push_back(stable);
  return lines;
}

void mark_not_converged(RenderFrame& frame, std::int64_t steps) {
  frame.banner = {"NOT CONVERGED", "(" + std::to_string(steps) + (steps == 1 ? " step)" : " steps)")};
}

void mark_wrong(RenderFrame& frame, const std::string& verdict) {
  std::string rest = verdict.rfind("WRONG: ", 0) == 0 ? verdict.substr(7) : verdict;
  frame.banner = {"WRONG"};
  for (std::size_t at; (at = rest.find(", ")) != std::string::npos; rest = rest.substr(at + 2))
    frame.banner.push_back(rest.substr(0, at));
  if (!rest.empty()) frame.banner.push_back(rest);
}

namespace {
// 10.0k, 1.23M: three figures and a suffix, short enough for a narrow tile.
std::string short_count(double n) {
  char buf[32];
  if (n >= 1e6) std::snprintf(buf, sizeof buf, "%.3gM", n / 1e6);
  else if (n >= 1e3) std::snprintf(buf, sizeof buf, "%.3gk", n / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f", n);
  return buf;
}
}  // namespace

std::string cost_line(double passes, double cpu_seconds, double t, bool cpu) {
  if (!(t > 0.0)) return short_count(passes) + " passes";
  std::string line = short_count(passes / t) + " passes/sim s";
  if (cpu) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "  %.0f ms cpu/sim s", 1e3 * cpu_seconds / t);
    line += buf;
  }
  return line;
}

}  // namespace clothsim::clip
