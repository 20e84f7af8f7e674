#include "plan_parts.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "clip/common/cli_common.h"
#include "scene/echo.h"
#include "scene/run_bounds.h"
#include "render/video/contact_sheet.h"

namespace clothsim::clip {

namespace {

// A finite number or fraction ("1/60") or a UsageError naming `option` and the text.
double parse_number(const std::string& text, const std::string& option) {
  const std::optional<double> value = parse_number_or_fraction(text);
  if (!value) throw UsageError(option + ": " + in_quotes(text) + " is not a number (or a fraction like 1/60)");
  return *value;
}

std::string seconds(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g s", t);
  return buf;
}

}  // namespace

std::vector<std::optional<double>> parse_dt_options(const std::string& text, const std::vector<IntegratorKind>& kinds) {
  std::vector<std::optional<double>> dts(kinds.size());
  if (trimmed(text).empty()) return dts;
  std::vector<bool> named(kinds.size(), false);
  bool bare_seen = false;
  auto check_step = [](double dt, const std::string& item) {
    if (!(dt > 0.0)) throw UsageError("--dt: step must be > 0 s, got " + in_quotes(item));
  };
  for (const std::string& raw : split_list(text)) {
    const std::string item = trimmed(raw);
    if (item.empty()) throw UsageError("--dt: empty item in " + in_quotes(text));
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      if (bare_seen) throw UsageError("--dt: more than one step for all runs in " + in_quotes(text));
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
      throw UsageError("--dt: unknown integrator " + in_quotes(name) + " (expected one of: " +
                       integrator_names_joined() + ")");
    const auto at = std::find(kinds.begin(), kinds.end(), *kind);
    if (at == kinds.end())
      throw UsageError("--dt: " + in_quotes(name) +
                       " is not one of the integrators being compared (a lane given as NAME@STEP has its own step)");
    const std::size_t i = static_cast<std::size_t>(at - kinds.begin());
    if (named[i]) throw UsageError("--dt: " + in_quotes(name) + " is given twice");
    const double dt = parse_number(trimmed(item.substr(eq + 1)), "--dt " + name);
    check_step(dt, item);
    dts[i] = dt;
    named[i] = true;
  }
  return dts;
}

std::vector<double> parse_dt_list(const std::string& text, const std::vector<IntegratorKind>& kinds,
                                  double scene_dt) {
  std::vector<double> dts;
  for (const std::optional<double>& dt : parse_dt_options(text, kinds)) dts.push_back(dt.value_or(scene_dt));
  return dts;
}

std::vector<double> parse_times(const std::string& text, double duration) {
  std::vector<double> times;
  for (const std::string& raw : split_list(text)) {
    const std::string item = trimmed(raw);
    if (item.empty()) throw UsageError("--times: empty item in " + in_quotes(text));
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

TargetPlan::TargetPlan(double duration, double fps, bool with_frames,
                       const std::vector<double>& sheet_times, double still_t, bool to_end)
    : duration_(duration), fps_(fps) {
  // duration * fps is bounded at validation (check_run_bounds), so the cast is defined.
  if (with_frames) frames_ = static_cast<long>(std::floor(duration * fps + 1e-9)) + 1;
  for (std::size_t c = 0; c < sheet_times.size(); ++c) extra_at(sheet_times[c]).column = static_cast<int>(c);
  if (still_t >= 0.0) extra_at(still_t).still = true;
  if ((frames_ == 0 && extras_.empty()) || to_end) extra_at(duration);
  size_ = frames_;
  for (Target& e : extras_) {
    e.frame = static_cast<int>(frame_at(e.t));
    if (e.frame < 0) ++size_;  // between frames: a target of its own
  }
}

TargetPlan& TargetPlan::with_scale_window(double scale_window) {
  if (frames_ > 0 || !(scale_window > 0.0)) return *this;  // clip frames are those instants already
  const long last = static_cast<long>(std::floor(std::min(scale_window, duration_) * fps_ + 1e-9));
  for (long k = 0; k <= last; ++k) {
    const std::size_t before = extras_.size();
    extra_at(std::min(static_cast<double>(k) / fps_, duration_));
    size_ += static_cast<long>(extras_.size() - before);  // frames_ == 0: every extra is a target
  }
  return *this;
}

Target& TargetPlan::extra_at(double t) {
  auto at = std::lower_bound(extras_.begin(), extras_.end(), t - 1e-6,
                             [](const Target& a, double v) { return a.t < v; });
  if (at != extras_.end() && std::abs(at->t - t) <= 1e-6) return *at;
  return *extras_.insert(at, Target{t, -1, -1, false});
}

double TargetPlan::last_time() const {
  const double frame = frames_ > 0 ? frame_time(frames_ - 1) : 0.0;
  if (extras_.empty()) return frame;
  const Target& e = extras_.back();
  return std::max(frame, e.frame >= 0 ? frame_time(e.frame) : e.t);  // (as Cursor hands it over)
}

double TargetPlan::frame_time(long k) const { return std::min(static_cast<double>(k) / fps_, duration_); }

long TargetPlan::frame_at(double t) const {
  if (frames_ == 0) return -1;
  const long k = std::clamp(static_cast<long>(std::llround(t * fps_)), 0L, frames_ - 1);
  for (long c : {k - 1, k, k + 1})  // the nearest frame, allowing for rounding either way
    if (c >= 0 && c < frames_ && std::abs(frame_time(c) - t) <= 1e-6) return c;
  return -1;
}

bool TargetPlan::Cursor::next(Target& out) {
  const TargetPlan& p = *plan_;
  const bool extra_left = extra_ < p.extras_.size();
  if (extra_left && (frame_ >= p.frames_ || p.extras_[extra_].frame == frame_ ||
                     p.extras_[extra_].t < p.frame_time(frame_))) {
    out = p.extras_[extra_++];
    if (out.frame >= 0) {
      out.t = p.frame_time(out.frame);  // the frame's own time, as when there is no extra
      frame_ = out.frame + 1;
    }
    return true;
  }
  if (frame_ >= p.frames_) return false;
  out = Target{p.frame_time(frame_), static_cast<int>(frame_), -1, false};
  ++frame_;
  return true;
}

std::string time_label(double t) {
  return "t = " + seconds(t);
}

namespace {

// A key a lane owns rather than its scene: varied, the lanes would run at the base scene's step
// or method under a label saying otherwise (--vary dt=1e-3,5e-4 ran both lanes at 1e-3 s).
void refuse_lane_key(const ParamKey& key, const std::string& values, const SceneDef& scene) {
  for (const std::string& path : key.paths) {
    std::string lanes;
    for (const std::string& item : split_list(values))
      lanes += (lanes.empty() ? "" : ",") + std::string(integrator_name(scene.integrator)) + "@" + trimmed(item);
    if (path == "dt")
      throw UsageError("--vary dt: a step belongs to a lane, not to the scene; give each lane its step, "
                       "--integrators " + lanes + " (bench: --dts " + trimmed(values) + ")");
    if (path == "integrator")
      throw UsageError("--vary integrator: the method is the lane itself; give --integrators " + trimmed(values));
  }
}

// Two values that are one number (100 and 1e2) would be two lanes of one scene under one label.
void refuse_repeats(const Variation& v, const std::string& text) {
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (v.values.empty() ? v.words[i] == v.words[j] : v.values[i] == v.values[j])
        throw UsageError("--vary: " + in_quotes(text) + " gives the value " +
                         (v.values.empty() ? v.words[i] : number_text(v.values[i])) + " twice (items " +
                         std::to_string(j + 1) + " and " + std::to_string(i + 1) + ")");
}

// The fewest figures (3 at least) that label every value apart: 100 and 100.0001 as
// "ks = 100" and "ks = 100.0001", never two lanes called (and filed as) "ks = 100".
int distinct_digits(const Variation& v) {
  for (int digits = 3; digits < 17; ++digits) {
    std::vector<std::string> labels;
    for (double value : v.values) labels.push_back(param_label(v.key, value, digits));
    std::sort(labels.begin(), labels.end());
    if (std::adjacent_find(labels.begin(), labels.end()) == labels.end()) return digits;
  }
  return 17;  // %.17g tells any two doubles apart
}

}  // namespace

Variation parse_vary(const std::string& text, const SceneDef& scene) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw UsageError("--vary: expected KEY=V1,V2,... (ks=2e3,2e4,2e5), got " + in_quotes(text));
  Variation v;
  try {
    v.key = resolve_param_key(text.substr(0, eq), scene);
  } catch (const ParamKeyError& e) {
    throw UsageError(std::string("--vary: ") + e.what());
  }
  refuse_lane_key(v.key, text.substr(eq + 1), scene);
  const auto word = [](const std::string& item) {
    return !item.empty() && std::all_of(item.begin(), item.end(), [](char c) { return std::islower(c) || c == '_'; });
  };
  for (const std::string& item : split_list(text.substr(eq + 1))) {
    const std::optional<double> value = parse_number_or_fraction(item);
    if (!value && !word(item)) throw UsageError("--vary: " + in_quotes(item) + " is neither a number nor a word");
    if (value) v.values.push_back(*value);
    else v.words.push_back(item);
  }
  if (!v.values.empty() && !v.words.empty())
    throw UsageError("--vary: " + in_quotes(text) + " mixes numbers and words; give one kind");
  refuse_repeats(v, text);
  v.digits = distinct_digits(v);
  return v;
}

std::vector<std::string> Variation::sets(std::size_t i) const {
  if (!values.empty()) return param_sets(key, values[i]);
  std::vector<std::string> out;
  for (const std::string& path : key.paths) out.push_back(path + "=" + words[i]);
  return out;
}

std::string Variation::label(std::size_t i) const {
  return values.empty() ? key.label + " = " + words[i] : param_label(key, values[i], digits);
}

void check_step_bounds(const SceneDef& scene, const std::vector<Lane>& lanes,
                       const std::optional<Lane>& reference) {
  for (const Lane& l : lanes) {
    const std::string too_long = run_bounds_problem(scene.duration, l.dt, scene.render.fps);
    if (!too_long.empty()) throw UsageError("--dt (" + l.spelling() + "): " + too_long);
  }
  if (!reference) return;
  const std::string too_long = run_bounds_problem(scene.duration, reference->dt, scene.render.fps);
  if (!too_long.empty())
    throw UsageError("--reference (" + reference->spelling() + ", for --color error): " + too_long +
                     "; give --reference NAME@STEP or --color checker");
}

std::vector<std::string> sheet_rows(const std::vector<Lane>& lanes, const std::vector<std::string>& labels) {
  std::vector<std::string> rows;
  for (std::size_t i = 0; i < lanes.size(); ++i) rows.push_back(labels.empty() ? lanes[i].label() : labels[i]);
  return rows;
}

void check_sheet_fits(int cell_w, int cell_h, const std::vector<std::string>& rows, int columns, int width,
                      int height) {
  try {
    contact_sheet_shrink(cell_w, cell_h, rows, columns, {}, width, height);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--sheet: ") + e.what() + "; give a larger --width/--height");
  }
}

}  // namespace clothsim::clip
