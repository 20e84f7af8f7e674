#include "colormap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace clothsim::render {

namespace {

// matplotlib's _viridis_data at indices round(k * 255 / 16), k = 0..16.
constexpr std::array<Rgb, kColormapPoints> kViridis = {{
    {0.267004f, 0.004874f, 0.329415f},
    {0.282327f, 0.094955f, 0.417331f},
    {0.278826f, 0.175490f, 0.483397f},
    {0.258965f, 0.251537f, 0.524736f},
    {0.229739f, 0.322361f, 0.545706f},
    {0.199430f, 0.387607f, 0.554642f},
    {0.172719f, 0.448791f, 0.557885f},
    {0.149039f, 0.508051f, 0.557250f},
    {0.127568f, 0.566949f, 0.550556f},
    {0.120081f, 0.622161f, 0.534946f},
    {0.153894f, 0.680203f, 0.504172f},
    {0.239374f, 0.735588f, 0.455688f},
    {0.360741f, 0.785964f, 0.387814f},
    {0.506271f, 0.828786f, 0.300362f},
    {0.668054f, 0.861999f, 0.196293f},
    {0.835270f, 0.886029f, 0.102646f},
    {0.993248f, 0.906157f, 0.143936f},
}};

// Removes what %g pads an exponent with: "1.5e-05" -> "1.5e-5", "2.5e+03" -> "2.5e3".
std::string compact_exponent(std::string s) {
  const auto e = s.find('e');
  if (e == std::string::npos) return s;
  std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+')) exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

}  // namespace

Rgb colormap(float t) {
  if (!std::isfinite(t)) t = 0.f;
  const float x = std::clamp(t, 0.f, 1.f) * static_cast<float>(kColormapPoints - 1);
  const int i = std::min(static_cast<int>(x), kColormapPoints - 2);
  const float f = x - static_cast<float>(i);
  const Rgb& a = kViridis[i];
  const Rgb& b = kViridis[i + 1];
  return {a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f};
}

std::array<std::uint8_t, 3> colormap_rgb8(float t) {
  const Rgb c = colormap(t);
  const auto byte = [](float v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.f, 1.f) * 255.f)); };
  return {byte(c[0]), byte(c[1]), byte(c[2])};
}

float scale_position(const ColorScale& scale, float value) {
  float p = 0.f;
  if (scale.log) {
    if (!(value > 0.f) || !std::isfinite(value)) return 0.f;  // no logarithm: the low end
    const double lo = std::log10(static_cast<double>(scale.lo)), hi = std::log10(static_cast<double>(scale.hi));
    p = static_cast<float>((std::log10(static_cast<double>(value)) - lo) / (hi - lo));
  } else {
    if (std::isnan(value)) return 0.f;
    p = static_cast<float>((static_cast<double>(value) - scale.lo) / (static_cast<double>(scale.hi) - scale.lo));
  }
  return std::clamp(p, 0.f, 1.f);
}

std::string short_number(double value) {
  if (value == 0.0) return "0";  // also -0
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return compact_exponent(buffer);
}

std::vector<ScaleTick> scale_ticks(const ColorScale& scale, int max_ticks) {
  max_ticks = std::max(max_ticks, 2);
  std::vector<ScaleTick> ticks;
  const auto add = [&](double v) { ticks.push_back({scale_position(scale, static_cast<float>(v)), short_number(v)}); };
  if (scale.log) {
    // The decades inside [lo, hi], a little slack for lo and hi written as 1e-6f.
    const double lo = std::log10(static_cast<double>(scale.lo)), hi = std::log10(static_cast<double>(scale.hi));
    const int first = static_cast<int>(std::ceil(lo - 1e-4)), last = static_cast<int>(std::floor(hi + 1e-4));
    const int count = last - first + 1;
    if (count < 2) {  // less than a decade or two: the ends say the range
      add(scale.lo);
      add(scale.hi);
      return ticks;
    }
    int step = 1;  // every decade, or every 2nd, 3rd ... to fit, counted from the top decade
    while ((count + step - 1) / step > max_ticks) ++step;
    // (from the top: the bar's upper end, which a scale from the data puts at a decade, is
    // always labelled; counted from exponent 0 instead, 1e-5 .. 1e-1 in three labels had read
    // 1e-4, 1e-2 and neither end)
    // One style on one bar: plain numbers when every decade is between 0.01 and 1000, else 1eN.
    const bool plain = first >= -2 && last <= 3;
    for (int d = first; d <= last; ++d) {
      if ((last - d) % step != 0) continue;
      const double v = std::pow(10.0, d);
      ticks.push_back({scale_position(scale, static_cast<float>(v)), plain ? short_number(v) : "1e" + std::to_string(d)});
    }
    return ticks;
  }
  // Linear: the smallest step of 1, 2 or 5 x 10^k that leaves at most max_ticks ticks.
  const double range = static_cast<double>(scale.hi) - scale.lo;
  const double magnitude = std::pow(10.0, std::floor(std::log10(range / (max_ticks - 1))));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * magnitude;
    if (std::floor(scale.hi / step + 1e-6) - std::ceil(scale.lo / step - 1e-6) + 1 <= max_ticks) break;
  }
  for (double k = std::ceil(scale.lo / step - 1e-6); k <= std::floor(scale.hi / step + 1e-6); k += 1.0) add(k * step);
  return ticks;
}

}  // namespace clothsim::render
