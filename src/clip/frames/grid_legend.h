// One colour bar per grid, outside the cloth: compare's tiles are drawn without their own
// (ColorScale::show_bar off), and the clip, the still and the sheet get the legend once, in a
// strip of the background colour at their right that no tile covers. The strip is sized to the
// picture's text (the grid's one text size) and taken out of the width asked for, so the
// picture stays the size asked for. Each lane's --frames PNGs are its tiles as the grid shows them.
#pragma once

#include "render/image.h"
#include "render/video/tiling.h"
#include "view/render_frame.h"
#include "view/vertex_fields.h"

namespace clothsim::clip {

// A grid of `layout` in width x height, with room at its right for the colour bar of `color`
// (none for FieldKind::None): the tiles are what the strip leaves.
struct LegendGrid {
  TileGrid grid;
  int legend_width = 0;  // pixels of the strip right of grid.width() (0: no colour bar)
  int width() const { return grid.width() + legend_width; }
};
LegendGrid fit_legend_grid(GridLayout layout, int width, int height, FieldKind color);

// The strip's width for `color` at text scale `scale` (0 for FieldKind::None).
int legend_width(FieldKind color, int scale);

// `body` with a strip `width` pixels wide at its right holding `legend` at text scale `scale`
// (nothing drawn in it for a null legend: the scale is not known yet), into `out`.
void add_legend_strip(const Image& body, const ColorScale* legend, int width, int scale, Image& out);

}  // namespace clothsim::clip
