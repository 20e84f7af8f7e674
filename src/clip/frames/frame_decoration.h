// What the pipeline adds to a lane's picture besides the overlay text: the colouring field
// with its scale, and the energy inset. Kept apart from the pipeline's control flow.
#pragma once

#include <cstddef>
#include <vector>

#include "frame_pipeline.h"
#include "view/render_frame.h"
#include "view/vertex_fields.h"

namespace clothsim::clip {

// Total energy of one lane over the targets so far, for the inset.
struct EnergyHistory {
  std::vector<float> t, e;
  void add(double time, double energy) {
    t.push_back(static_cast<float>(time));
    e.push_back(static_cast<float>(energy));
  }
};

// The logarithmic scale `range` of a field, labelled with the field and its unit.
ColorScale field_scale(FieldKind kind, const ColorRange& range);

// Colours the cloth by `field` (one value per particle) on field_scale(kind, range), with its
// colour bar in the picture unless `bar_outside` (a tile: the grid draws one for all).
void color_by_field(RenderFrame& frame, const std::vector<float>& field, FieldKind kind, const ColorRange& range,
                    bool bar_outside = false);

// The inset of lane `lane`'s energy over [0, duration], on axes shared by every lane, zero
// included. Against `reference` (compare: the reference lane's total energy, run alongside) it
// is E(t) - E_ref(t), the reference interpolated to the lane's sample times and the curve
// stopping at the reference's last sample: what the method gains or loses beyond the true
// motion's own damping, which on a damped drape differs between lanes where E - E(0) does not.
// Without one (run, --vary) it is E(t) - E(0). Lanes marked in `diverged` set the axis only
// when every lane is, and no axis reaches past 2 |E(0)| either way: a blow-up would otherwise
// flatten the rest (its curve runs along the edge).
void draw_energy_inset(RenderFrame& frame, const std::vector<EnergyHistory>& lanes, std::size_t lane, double duration,
                       const EnergyHistory* reference = nullptr, const std::vector<bool>& diverged = {});

}  // namespace clothsim::clip
