#include "frame_decoration.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim::cli {

void color_by_field(RenderFrame& frame, const std::vector<float>& field, FieldKind kind, const ColorRange& range) {
  frame.cloth_field = field;
  frame.color_scale.lo = static_cast<float>(range.lo);
  frame.color_scale.hi = static_cast<float>(range.hi);
  frame.color_scale.log = true;
  frame.color_scale.label = field_label(kind);
  frame.color_scale.show_bar = true;
}

void draw_energy_inset(RenderFrame& frame, const std::vector<EnergyHistory>& lanes, std::size_t lane, double duration) {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (const EnergyHistory& h : lanes)
    for (float e : h.e)
      if (std::isfinite(e)) {
        lo = std::min(lo, e);
        hi = std::max(hi, e);
      }
  if (!(lo <= hi)) return;  // nothing finite yet
  // A lane whose energy explodes before it is declared diverged would flatten every other
  // curve: the axis reaches at most 2 |E(0)| either side of the initial energy (the same in
  // every lane: one scene), and what lies beyond is drawn on the axis' edge.
  float e0 = std::numeric_limits<float>::quiet_NaN();
  for (const EnergyHistory& h : lanes)
    if (!h.e.empty() && std::isfinite(h.e.front())) {
      e0 = h.e.front();
      break;
    }
  if (std::isfinite(e0) && std::abs(e0) > 0.f) {
    lo = std::max(lo, e0 - 2.f * std::abs(e0));
    hi = std::min(hi, e0 + 2.f * std::abs(e0));
  }
  if (hi - lo < 1e-6f * std::max(1.f, std::abs(hi))) {  // a flat line: give it room
    const float pad = std::max(1e-3f, 0.05f * std::abs(hi));
    lo -= pad;
    hi += pad;
  }
  auto& inset = frame.inset;
  inset.show = true;
  inset.t = lanes[lane].t;
  inset.value = lanes[lane].e;
  inset.t_lo = 0.f;
  inset.t_hi = static_cast<float>(std::max(duration, 1e-9));
  inset.v_lo = lo;
  inset.v_hi = hi;
  inset.label = "total energy [J]";
}

}  // namespace clothsim::cli
