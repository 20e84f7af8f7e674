#include "compare_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "cli_common.h"

namespace clothsim::cli {

namespace {

// A finite number or fraction ("1/60") or a UsageError naming `option` and the text.
double parse_number(const std::string& text, const std::string& option) {
  const std::optional<double> value = parse_number_or_fraction(text);
  if (!value) throw UsageError(option + ": '" + text + "' is not a number (or a fraction like 1/60)");
  return *value;
}

std::string seconds(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", t);
  return buf;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

}  // namespace

std::vector<double> parse_dt_list(const std::string& text, const std::vector<IntegratorKind>& kinds,
                                  double scene_dt) {
  std::vector<double> dts(kinds.size(), scene_dt);
  if (trimmed(text).empty()) return dts;
  std::vector<bool> named(kinds.size(), false);
  bool bare_seen = false;
  auto check_step = [](double dt, const std::string& item) {
    if (!(dt > 0.0)) throw UsageError("--dt: step must be > 0 s, got '" + item + "'");
  };
  for (const std::string& raw : split_list(text)) {
    const std::string item = trimmed(raw);
    if (item.empty()) throw UsageError("--dt: empty item in '" + text + "'");
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      if (bare_seen) throw UsageError("--dt: more than one step for all runs in '" + text + "'");
      bare_seen = true;
      const double dt = parse_number(item, "--dt");
      check_step(dt, item);
      for (std::size_t i = 0; i < kinds.size(); ++i)
        if (!named[i]) dts[i] = dt;
      continue;
    }
    const std::string name = trimmed(item.substr(0, eq));
    const auto kind = parse_integrator(name);
    if (!kind)
      throw UsageError("--dt: unknown integrator '" + name + "' (expected one of: " +
                       integrator_names_joined() + ")");
    const auto at = std::find(kinds.begin(), kinds.end(), *kind);
    if (at == kinds.end())
      throw UsageError("--dt: '" + name + "' is not one of the integrators being compared");
    const std::size_t i = static_cast<std::size_t>(at - kinds.begin());
    if (named[i]) throw UsageError("--dt: '" + name + "' is given twice");
    const double dt = parse_number(trimmed(item.substr(eq + 1)), "--dt " + name);
    check_step(dt, item);
    dts[i] = dt;
    named[i] = true;
  }
  return dts;
}

std::vector<double> parse_times(const std::string& text, double duration) {
  std::vector<double> times;
  for (const std::string& raw : split_list(text)) {
    const std::string item = trimmed(raw);
    if (item.empty()) throw UsageError("--times: empty item in '" + text + "'");
    const double t = parse_number(item, "--times");
    if (t < 0.0 || t > duration + 1e-9)
      throw UsageError("--times: " + item + " s is outside the run (0 to " + seconds(duration) + ")");
    if (!times.empty() && t <= times.back())
      throw UsageError("--times: times must increase, but " + item + " follows " +
                       seconds(times.back()));
    times.push_back(t);
  }
  if (times.empty()) throw UsageError("--times: no time given");
  return times;
}

std::vector<Target> plan_targets(double duration, double fps, bool with_frames,
                                 const std::vector<double>& sheet_times, double still_t) {
  std::vector<Target> targets;
  if (with_frames) {
    const int last = static_cast<int>(std::floor(duration * fps + 1e-9));
    for (int k = 0; k <= last; ++k) targets.push_back(Target{std::min(k / fps, duration), k, -1, false});
  }
  // The target at time t, inserted in order unless one is already within a microsecond.
  auto target_at = [&targets](double t) -> Target& {
    auto at = std::lower_bound(targets.begin(), targets.end(), t - 1e-6,
                               [](const Target& a, double v) { return a.t < v; });
    if (at != targets.end() && std::abs(at->t - t) <= 1e-6) return *at;
    return *targets.insert(at, Target{t, -1, -1, false});
  };
  for (std::size_t c = 0; c < sheet_times.size(); ++c)
    target_at(sheet_times[c]).column = static_cast<int>(c);
  if (still_t >= 0.0) target_at(still_t).still = true;
  if (targets.empty()) targets.push_back(Target{duration, -1, -1, false});
  return targets;
}

int count_frames(const std::vector<Target>& targets) {
  return static_cast<int>(std::count_if(targets.begin(), targets.end(),
                                        [](const Target& t) { return t.frame >= 0; }));
}

std::string time_label(double t) {
  return "t = " + seconds(t);
}

}  // namespace clothsim::cli
