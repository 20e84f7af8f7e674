// The series inset: a small graph of one quantity over time (total energy, in the comparison
// clips), so explicit Euler's gain and implicit Euler's loss show in the clip itself. Drawn on
// the CPU after read-back, deterministically: a dark translucent panel at the bottom-right
// (overlay_layout.h) with the label, the axis ranges the frame gives (v_hi top-left and v_lo
// bottom-left inside the graph, t_lo and t_hi under it) and the curve of the samples so far,
// its last point marked. Values past the axis range are drawn on its edge; a non-finite
// sample breaks the curve.
#pragma once

#include "image.h"
#include "overlay_layout.h"
#include "view/render_frame.h"

namespace clothsim::render {

void draw_series_inset(Image& image, const SeriesInset& inset, const OverlayLayout& layout);

}  // namespace clothsim::render
