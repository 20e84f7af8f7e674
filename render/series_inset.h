// The series inset: a small graph of one quantity over time (the energy change E(t) - E(0), in
// the comparison clips), so a lane that gains energy or blows up shows in the clip itself. Drawn
// on the CPU after read-back, deterministically: a dark translucent panel at the bottom-right
// (overlay_layout.h) with the label, the axis ranges the frame gives (v_hi top-right and v_lo
// bottom-right inside the graph, where the curve arrives last; t_lo and t_hi under it) and the
// curve of the samples so far, its last point marked. Values past the axis range are drawn on
// its edge; a non-finite sample breaks the curve.
#pragma once

#include "image.h"
#include "overlay_layout.h"
#include "view/render_frame.h"

namespace clothsim::render {

void draw_series_inset(Image& image, const SeriesInset& inset, const OverlayLayout& layout);

}  // namespace clothsim::render
