// The colour scale of a per-particle field (RenderFrame::cloth_field): the colormap, the
// value -> position mapping and the tick labels of the colour bar. One definition on the CPU:
// the renderer uploads colormap() as a 256-texel texture the cloth shader samples, and the
// colour bar is drawn from the same function, so the cloth and its legend cannot disagree.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "view/render_frame.h"

namespace clothsim::render {

// Viridis (van der Walt and Smith, matplotlib 2.0; CC0): perceptually uniform, lightness
// rising monotonically from dark purple to yellow, readable in greyscale and by the common
// colour-vision deficiencies. 17 control points (every 16th of matplotlib's 256), linear in
// display sRGB between them. t is clamped to [0, 1]; a non-finite t gives the low end.
constexpr int kColormapPoints = 17;
Rgb colormap(float t);
std::array<std::uint8_t, 3> colormap_rgb8(float t);  // rounded to the nearest byte

// Where `value` falls on the scale, 0 at lo and 1 at hi, clamped. On a log scale by log10;
// there values <= 0 and non-finite values map to 0. On a linear scale NaN maps to 0.
float scale_position(const ColorScale& scale, float value);

// A labelled tick of the colour bar.
struct ScaleTick {
  float position;    // 0..1 on the bar, as scale_position
  std::string text;  // "1e-4", "0.01", "2.5"
};

// Ticks for a bar with room for at most `max_ticks` labels (>= 2). Log scale: the decades
// inside [lo, hi], every one or every n-th (n dividing the exponent) when there are too many,
// written "1e-4" (or "0.01" ... "1000" when all of them are in that range); with fewer than
// two decades inside, lo and hi themselves. Linear: multiples of 1, 2 or 5 x 10^k inside [lo, hi].
std::vector<ScaleTick> scale_ticks(const ColorScale& scale, int max_ticks);

// A number short enough for a tick or an axis: 3 significant digits, exponent written compactly
// ("1.5e-5", "2.5e3", "0.01", "120").
std::string short_number(double value);

}  // namespace clothsim::render
