// Per-particle fields a picture can be coloured by (render.color, --color): how far each
// particle is from a reference solution, how strained the springs around it are, how fast it
// moves. Values in the field's own units, one per cloth particle; the renderer maps them
// through a colour scale (RenderFrame::cloth_field).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/model.h"
#include "core/model/state.h"

namespace clothsim {

enum class FieldKind { None, Error, Strain, Speed };  // None: the checker

std::optional<FieldKind> parse_field_kind(std::string_view name);  // "checker", "error", ...
std::string_view field_kind_name(FieldKind kind);                  // "checker" for None
std::string field_label(FieldKind kind);                           // "error [m]", "strain", ...
std::string field_unit(FieldKind kind);                            // " m", "", " m/s"

// Strain |l / l0 - 1| of the springs at each particle, averaged over the springs that end
// there (all three families); 0 for a particle no spring reaches.
std::vector<float> vertex_strain(const Model& model, const State& state);

// |v| of each particle, m/s.
std::vector<float> vertex_speed(const Model& model, const State& state);

// |x_i - r_i| of each particle, m, from positions (3 x P, column-major) of two runs of one
// model at the same time. Computed in double: the differences a reference resolves (1e-9 m on
// a 1 m cloth) are below float's resolution of the positions themselves.
std::vector<float> vertex_distance(const std::vector<double>& x, const std::vector<double>& reference);

}  // namespace clothsim
