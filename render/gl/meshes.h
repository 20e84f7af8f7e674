// Fixed meshes the renderer builds: the unit spheres every sphere is drawn from, one per
// level of detail a frame has asked for.
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

// The most a sphere's outline may stray inside the true circle on screen, in pixels: a quarter
// of a pixel, below what 4x MSAA resolves (the old fixed 64 x 32 mesh strayed 0.22 px on a
// sphere a third of a 1080p frame high).
constexpr float kSphereOutlineErrorPx = 0.25f;

// How finely to facet a sphere `radius_px` pixels in radius on screen: the fewest slices, a
// multiple of 4 from 12 to 128, for stacks = slices / 2, whose outline strays at most
// `max_error_px` from the circle. Every facet spans 2 pi / slices of arc either way, so a chord
// of the outline lies radius (1 - cos(pi / slices)) inside it at its middle. Why it matters:
// llvmpipe pays for every triangle's setup and for every sample of it, and a fixed fine mesh
// cost a compare tile a quarter of its render time for spheres 60-100 px across.
int sphere_slices(float radius_px, float max_error_px = kSphereOutlineErrorPx);

}  // namespace clothsim
