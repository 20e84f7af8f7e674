// SceneDef -> Model: the compiler from a validated scene to the engine's immutable model (as
// MuJoCo's compiler stands outside its engine), and the grid selections scenes name.
#pragma once

#include <vector>

#include "core/model/model.h"
#include "scene/scene_def.h"

namespace clothsim {

// Builds the immutable model. The SceneDef must have passed validation (the parser does it).
Model build_model(const SceneDef& scene);

// The particles (index j * nx + i) a selection names on an nx x ny grid, sorted, each once
// (corners of a 1 x 1 grid, or an edge and a range that overlap, count once).
std::vector<int> selected_particles(const std::vector<GridSelection>& selection, int nx, int ny);

}  // namespace clothsim
