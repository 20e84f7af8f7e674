#include "grid_legend.h"

#include <algorithm>
#include <string>

#include "render/color_bar.h"
#include "render/text.h"

namespace clothsim::clip {

int legend_width(FieldKind color, int scale) {
  return color == FieldKind::None ? 0 : render::color_bar_strip_width(field_label(color), scale);
}

LegendGrid fit_legend_grid(GridLayout layout, int width, int height, FieldKind color) {
  // The strip's text is the tiles' (one size per grid), and their height does not depend on it.
  const TilingStyle style;
  const int cell_h = (height - (layout.rows - 1) * style.gutter) / layout.rows;
  const int strip = legend_width(color, text_scale_for_height(std::max(cell_h, 1)));
  if (strip > 0 && width - strip < layout.columns * (style.gutter + 1))
    throw LayoutError("a " + std::to_string(layout.columns) + "x" + std::to_string(layout.rows) + " grid and the colour bar's " +
                      std::to_string(strip) + "-pixel strip do not fit in " + std::to_string(width) + "x" +
                      std::to_string(height) + " pixels (--color checker draws no bar)");
  return LegendGrid{TileGrid::fit(layout, width - strip, height, style), strip};
}

void add_legend_strip(const Image& body, const ColorScale* legend, int width, int scale, Image& out) {
  if (out.width != body.width + width || out.height != body.height) out = Image(body.width + width, body.height);
  fill_rect(out, body.width, 0, width, body.height, TilingStyle{}.background);
  blit(body, out, 0, 0);
  if (legend) render::draw_color_bar_strip(out, *legend, {body.width, 0, width, body.height}, scale);
}

}  // namespace clothsim::clip
