#include "image_diff.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace clothsim {

DiffStats compare_images(const Image& a, const Image& b, int pixel_threshold) {
  DiffStats stats;
  const std::size_t pixels = static_cast<std::size_t>(a.width) * a.height;
  if (pixels == 0 || a.width != b.width || a.height != b.height) return stats;
  double sum_squares = 0.0;
  std::size_t over = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    const std::uint8_t* p = &a.rgba[4 * i];
    const std::uint8_t* q = &b.rgba[4 * i];
    int pixel_max = 0;
    for (int c = 0; c < 3; ++c) {  // RGB; alpha is always 255 in rendered frames
      const int d = std::abs(static_cast<int>(p[c]) - static_cast<int>(q[c]));
      sum_squares += static_cast<double>(d) * d;
      pixel_max = std::max(pixel_max, d);
    }
    stats.max = std::max(stats.max, pixel_max);
    if (pixel_max > pixel_threshold) ++over;
  }
  stats.rms = std::sqrt(sum_squares / (3.0 * static_cast<double>(pixels)));
  stats.over_fraction = static_cast<double>(over) / static_cast<double>(pixels);
  return stats;
}

bool within_tolerance(const DiffStats& stats, const DiffTolerance& tol) {
  return stats.rms <= tol.max_rms && stats.over_fraction <= tol.max_over_fraction;
}

Image diff_image(const Image& a, const Image& b, int gain) {
  Image out(a.width, a.height);
  if (a.width != b.width || a.height != b.height) return out;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::uint8_t* p = a.pixel(x, y);
      const std::uint8_t* q = b.pixel(x, y);
      std::uint8_t* o = out.pixel(x, y);
      // A dim grey copy of `a` shows where things are; the amplified difference is laid
      // over it in a heat colour (red, then yellow, then white) so small changes stand out.
      const int grey = (p[0] * 77 + p[1] * 150 + p[2] * 29) >> 8;  // Rec. 601 luma
      int d = 0;
      for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(static_cast<int>(p[c]) - static_cast<int>(q[c])));
      const int heat = std::min(765, d * gain * 3);  // 0..765 across the three ramps
      const int base = grey / 4;
      o[0] = static_cast<std::uint8_t>(std::min(255, base + std::min(heat, 255)));
      o[1] = static_cast<std::uint8_t>(std::min(255, base + std::clamp(heat - 255, 0, 255)));
      o[2] = static_cast<std::uint8_t>(std::min(255, base + std::clamp(heat - 510, 0, 255)));
      o[3] = 255;
    }
  return out;
}

}  // namespace clothsim
