// Fixed meshes the renderer builds once: the unit sphere every sphere is drawn from.
#pragma once

#include <cstdint>
#include <vector>

namespace clothsim {

struct Mesh {
  std::vector<float> positions;         // (3 x V)
  std::vector<float> normals;           // (3 x V) unit
  std::vector<std::uint32_t> triangles;  // (3 x T) counter-clockwise seen from outside
};

// A latitude-longitude unit sphere centred at the origin: `slices` around the y axis,
// `stacks` from pole to pole. Normals equal positions, so shading is smooth.
Mesh make_unit_sphere(int slices, int stacks);

}  // namespace clothsim
