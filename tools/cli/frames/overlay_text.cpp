#include "overlay_text.h"

#include <cstdio>

namespace clothsim::cli {

std::vector<std::string> overlay_lines(const Model& model, const std::string& lane_label, double t) {
  return {model.name, lane_label, overlay_time_line(t)};
}

std::vector<std::string> overlay_lines(const Model& model, IntegratorKind kind, double dt, double t) {
  char step[32];
  std::snprintf(step, sizeof step, "%.3g", dt);
  return overlay_lines(model, integrator_label(integrator_name(kind), step), t);
}

std::string integrator_label(std::string_view name, std::string_view step) {
  return std::string(name) + "  dt = " + std::string(step) + " s";
}

std::string overlay_time_line(double t) {
  char line[48];
  std::snprintf(line, sizeof line, "t = %.3f s", t);
  return line;
}

void mark_diverged(RenderFrame& frame, const Divergence& divergence) {
  // The time as `run` prints it (%.6g), and the step: the picture and the exit message agree.
  char time[48];
  std::snprintf(time, sizeof time, "at t = %.6g s", divergence.t);
  frame.banner = {"DIVERGED", time, "(step " + std::to_string(divergence.step) + ")"};
  frame.overlay_lines.push_back("diverged: " + divergence.reason);
}

void mark_not_converged(RenderFrame& frame, std::int64_t steps) {
  frame.banner = {"NOT CONVERGED", "(" + std::to_string(steps) + (steps == 1 ? " step)" : " steps)")};
}

}  // namespace clothsim::cli
