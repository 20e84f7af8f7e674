#include "series_inset.h"

#include <algorithm>
#include <cmath>

#include "colormap.h"
#include "text.h"

namespace clothsim::render {

namespace {

const Rgba8 kWhite{255, 255, 255, 255};
const Rgba8 kAxisText{200, 200, 200, 255};
const Rgba8 kAxis{140, 140, 140, 255};
const Rgba8 kCurve{255, 204, 64, 255};  // amber: stands out on the dark panel, unlike any viridis hue

// A square of side `size` centred on (x, y), clipped to `clip`.
void dot(Image& image, int x, int y, int size, const ImageBox& clip, Rgba8 color) {
  for (int py = y - size / 2; py < y - size / 2 + size; ++py)
    for (int px = x - size / 2; px < x - size / 2 + size; ++px)
      if (clip.contains(px, py) && px >= 0 && py >= 0 && px < image.width && py < image.height)
        std::copy(color.begin(), color.end(), image.pixel(px, py));
}

// A line of `size` px squares stepped one pixel at a time along its longer axis (a DDA),
// rounding to the nearest pixel: exact integers, so identical everywhere.
void line(Image& image, double x0, double y0, double x1, double y1, int size, const ImageBox& clip, Rgba8 color) {
  const int steps = static_cast<int>(std::ceil(std::max(std::fabs(x1 - x0), std::fabs(y1 - y0))));
  for (int i = 0; i <= steps; ++i) {
    const double f = steps == 0 ? 0.0 : static_cast<double>(i) / steps;
    dot(image, static_cast<int>(std::lround(x0 + (x1 - x0) * f)), static_cast<int>(std::lround(y0 + (y1 - y0) * f)),
        size, clip, color);
  }
}

}  // namespace

void draw_series_inset(Image& image, const SeriesInset& inset, const OverlayLayout& l) {
  if (l.inset.empty()) return;
  const int s = l.inset_scale, pad = 2 * s;
  const ImageBox& plot = l.plot;
  darken_rect(image, l.inset.x, l.inset.y, l.inset.right(), l.inset.bottom());
  if (!inset.label.empty()) draw_text(image, l.inset.x + pad, l.inset.y + pad, inset.label, kWhite, s, false);

  // Axes on the left and bottom edges of the graph; the ranges written inside and under it.
  const int axis = std::max(1, s / 2);
  fill_box(image, {plot.x, plot.y, axis, plot.h}, kAxis);
  fill_box(image, {plot.x, plot.bottom() - axis, plot.w, axis}, kAxis);
  // The value range at the right edge: the curve grows from the left and reaches it only at the end.
  const std::string v_hi = short_number(inset.v_hi), v_lo = short_number(inset.v_lo);
  draw_text(image, plot.right() - s - text_width(v_hi, s), plot.y + s, v_hi, kAxisText, s, false);
  draw_text(image, plot.right() - s - text_width(v_lo, s), plot.bottom() - axis - s - kTextCapHeight * s, v_lo,
            kAxisText, s, false);
  const int axis_label_y = plot.bottom() + s;
  const std::string t_lo = short_number(inset.t_lo) + " s", t_hi = short_number(inset.t_hi) + " s";
  draw_text(image, plot.x, axis_label_y, t_lo, kAxisText, s, false);
  draw_text(image, plot.right() - text_width(t_hi, s), axis_label_y, t_hi, kAxisText, s, false);

  // The curve over the samples so far, in pixel centres of the graph area.
  struct Point {
    bool valid = false;
    double x = 0.0, y = 0.0;
  };
  const double t_span = static_cast<double>(inset.t_hi) - inset.t_lo, v_span = static_cast<double>(inset.v_hi) - inset.v_lo;
  const auto to_pixel = [&](float t, float v) {
    Point p;
    if (!std::isfinite(t) || !std::isfinite(v) || t < inset.t_lo || t > inset.t_hi) return p;
    const double fx = (t - inset.t_lo) / t_span;
    const double fy = std::clamp((v - inset.v_lo) / v_span, 0.0, 1.0);  // past the range: on its edge
    p.valid = true;
    p.x = plot.x + axis + fx * (plot.w - axis - 1);
    p.y = plot.y + (1.0 - fy) * (plot.h - axis - 1);
    return p;
  };
  const auto round = [](double v) { return static_cast<int>(std::lround(v)); };
  const int thickness = std::max(1, (s + 1) / 2);
  Point previous, last;
  const std::size_t n = std::min(inset.t.size(), inset.value.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Point p = to_pixel(inset.t[i], inset.value[i]);
    if (p.valid && previous.valid) line(image, previous.x, previous.y, p.x, p.y, thickness, plot, kCurve);
    if (p.valid && !previous.valid) dot(image, round(p.x), round(p.y), thickness, plot, kCurve);
    previous = p;  // a gap (non-finite, outside the time axis) breaks the curve
    if (p.valid) last = p;
  }
  if (last.valid) dot(image, round(last.x), round(last.y), 3 * thickness, plot, kCurve);  // where it is now
}

}  // namespace clothsim::render
