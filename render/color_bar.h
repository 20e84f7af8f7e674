// The colour bar: the legend of a field-coloured cloth, drawn on the CPU after read-back (as
// the text is), so it is byte-identical on every machine and GL backend. A dark panel at the
// right edge (overlay_layout.h) holds the scale's label with its units, the gradient of
// colormap() from hi (top) to lo (bottom) with a thin light frame, and tick labels left of it:
// decades on a log scale ("1e-4"), round values on a linear one. Enough for a still or a
// contact-sheet cell to be read on its own.
#pragma once

#include "image.h"
#include "overlay_layout.h"
#include "view/render_frame.h"

namespace clothsim::render {

void draw_color_bar(Image& image, const ColorScale& scale, const OverlayLayout& layout);

// The same legend once for a whole grid, in `strip` beside its tiles (layout_color_bar_strip),
// at the grid's text scale: the tiles are drawn without their own (ColorScale::show_bar false).
void draw_color_bar_strip(Image& image, const ColorScale& scale, const ImageBox& strip, int text_scale);

}  // namespace clothsim::render
