// Engine -> renderer: fill a RenderFrame from the model and state (positions, normals,
// spheres, ground, camera). The only place the engine meets rendering. The snapshot is data
// only: the words over it (overlay lines, lane labels, DIVERGED banners) are presentation and
// are written by the tools that show it (tools/cli/overlay_text.h).
#pragma once

#include "model.h"
#include "render_frame.h"
#include "state.h"

namespace clothsim {

RenderFrame make_render_frame(const Model& model, const State& state);

}  // namespace clothsim
