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

}  // namespace clothsim::render
