#include "color_bar.h"

#include <algorithm>
#include <cmath>

#include "text.h"

namespace clothsim::render {

namespace {

const Rgba8 kWhite{255, 255, 255, 255};
const Rgba8 kFrame{220, 220, 220, 255};

}  // namespace

void draw_color_bar(Image& image, const ColorScale& scale, const OverlayLayout& l) {
  if (l.color_bar.empty()) return;
  const int s = l.scale, pad = 2 * s;
  darken_rect(image, l.color_bar.x, l.color_bar.y, l.color_bar.right(), l.color_bar.bottom());
  if (!scale.label.empty())
    draw_text(image, l.color_bar.right() - pad - text_width(scale.label, s), l.title_y, scale.label, kWhite, s,
              /*backdrop=*/false);

  const ImageBox& bar = l.bar;
  fill_box(image, {bar.x - 1, bar.y - 1, bar.w + 2, bar.h + 2}, kFrame);  // a 1 px frame around the gradient
  for (int row = 0; row < bar.h; ++row) {  // row centres: hi at the top, lo at the bottom
    const float t = 1.f - (static_cast<float>(row) + 0.5f) / static_cast<float>(bar.h);
    const auto c = colormap_rgb8(t);
    fill_box(image, {bar.x, bar.y + row, bar.w, 1}, {c[0], c[1], c[2], 255});
  }

  const int tick_len = 2 * s, thickness = std::max(1, s / 2);
  for (const ScaleTick& tick : l.ticks) {
    const int y = bar.y + static_cast<int>(std::lround((1.f - tick.position) * static_cast<float>(bar.h - 1)));
    fill_box(image, {bar.x - 1 - tick_len, y - thickness / 2, tick_len, thickness}, kWhite);
    const int x = bar.x - 1 - tick_len - s - text_width(tick.text, s);
    draw_text(image, x, y - (kTextCapHeight * s) / 2, tick.text, kWhite, s, /*backdrop=*/false);
  }
}

void draw_color_bar_strip(Image& image, const ColorScale& scale, const ImageBox& strip, int text_scale) {
  draw_color_bar(image, scale, layout_color_bar_strip(scale, strip, text_scale));
}

}  // namespace clothsim::render
