#include "frame_decoration.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothsim::clip {

ColorScale field_scale(FieldKind kind, const ColorRange& range) {
  ColorScale scale;
  scale.lo = static_cast<float>(range.lo);
  scale.hi = static_cast<float>(range.hi);
  scale.log = true;
  scale.label = field_label(kind);
  return scale;
}

void color_by_field(RenderFrame& frame, const std::vector<float>& field, FieldKind kind, const ColorRange& range,
                    bool bar_outside) {
  frame.cloth_field = field;
  frame.color_scale = field_scale(kind, range);
  frame.color_scale.show_bar = !bar_outside;
}

namespace {

// The lanes' common initial energy (one scene): the first finite first sample, NaN if none.
float initial_energy(const std::vector<EnergyHistory>& lanes) {
  for (const EnergyHistory& h : lanes)
    if (!h.e.empty() && std::isfinite(h.e.front())) return h.e.front();
  return std::numeric_limits<float>::quiet_NaN();
}

}  // namespace

namespace {

// What a lane's inset plots: E(t) - E_ref(t) at its sample times up to the reference's last
// sample (linear between the reference's samples), or E(t) - e0 without a reference.
EnergyHistory inset_curve(const EnergyHistory& lane, const EnergyHistory* reference, float e0) {
  EnergyHistory out;
  std::size_t j = 0;
  for (std::size_t i = 0; i < lane.t.size(); ++i) {
    const float t = lane.t[i];
    if (!reference) {
      out.t.push_back(t);
      out.e.push_back(lane.e[i] - e0);
      continue;
    }
    const std::vector<float>&rt = reference->t, &re = reference->e;
    if (rt.empty() || t > rt.back() + 1e-6f) break;  // not yet known there
    while (j + 1 < rt.size() && rt[j + 1] < t) ++j;
    float ref = re[j];
    if (j + 1 < rt.size() && rt[j + 1] > rt[j] && t > rt[j])
      ref += (re[j + 1] - re[j]) * (t - rt[j]) / (rt[j + 1] - rt[j]);
    out.t.push_back(t);
    out.e.push_back(lane.e[i] - ref);
  }
  return out;
}

}  // namespace

void draw_energy_inset(RenderFrame& frame, const std::vector<EnergyHistory>& lanes, std::size_t lane, double duration,
                       const EnergyHistory* reference, const std::vector<bool>& diverged) {
  const float e0 = initial_energy(lanes);
  if (!std::isfinite(e0)) return;  // nothing finite yet
  // The change rather than the total: the lanes share E(0), so what each gains or loses is what
  // differs, and a few joules apart no longer sit on one line at 5e3 J.
  const bool all_diverged = std::all_of(diverged.begin(), diverged.end(), [](bool d) { return d; });
  float lo = 0.f, hi = 0.f;
  std::vector<EnergyHistory> curves;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    curves.push_back(inset_curve(lanes[k], reference, e0));
    if (k < diverged.size() && diverged[k] && !all_diverged) continue;
    for (float e : curves.back().e)
      if (std::isfinite(e)) lo = std::min(lo, e), hi = std::max(hi, e);
  }
  // A lane whose energy explodes before it is declared diverged would flatten every other
  // curve: the axis reaches at most 2 |E(0)| either way, and what lies beyond is drawn on its edge.
  const float cap = 2.f * std::max(std::abs(e0), 1e-3f);
  lo = std::max(lo, -cap);
  hi = std::min(hi, cap);
  if (hi - lo < 1e-6f * std::max(1.f, std::abs(e0))) {  // a flat line: give it room
    const float pad = std::max(1e-3f, 0.05f * std::abs(e0));
    lo -= pad;
    hi += pad;
  }
  auto& inset = frame.inset;
  inset.show = true;
  inset.t = curves[lane].t;
  inset.value = curves[lane].e;
  inset.t_lo = 0.f;
  inset.t_hi = static_cast<float>(std::max(duration, 1e-9));
  inset.v_lo = lo;
  inset.v_hi = hi;
  inset.label = reference ? "E-Eref [J]" : "E-E(0) [J]";
}

}  // namespace clothsim::clip
