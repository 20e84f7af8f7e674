// Engine -> renderer: fill a RenderFrame from the model, the state and the scene's render
// settings (positions, normals, spheres, ground, camera). The only place the engine meets rendering. The snapshot is data
// only: the words over it (overlay lines, lane labels, DIVERGED banners) are presentation and
// are written by the tools that show it (src/clip/frames/overlay_text.h).
#pragma once

#include "render_frame.h"
#include "render_settings.h"
#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

RenderFrame make_render_frame(const Model& model, const State& state, const RenderDef& look);

// The camera of `render.camera: auto` for a picture of `aspect` (width / height): fitted
// (camera_fit.h) to the scene at rest with the scene's lens, from 40 degrees above the horizon
// rather than the fit's 30, so a cloth sagging over its ball keeps about a third of a tile.
// What run, compare and the Python module's render() aim with.
RenderCamera fit_scene_camera(const Model& model, const RenderDef& look, double aspect);

}  // namespace clothsim
