#include "meshes.h"

#include <algorithm>
#include <cmath>

namespace clothsim {

Mesh make_unit_sphere(int slices, int stacks) {
  Mesh mesh;
  const double pi = 3.14159265358979323846;
  for (int j = 0; j <= stacks; ++j) {
    const double polar = pi * j / stacks;  // 0 at +y, pi at -y
    for (int i = 0; i <= slices; ++i) {
      const double azimuth = 2.0 * pi * i / slices;
      const float p[3] = {static_cast<float>(std::sin(polar) * std::cos(azimuth)),
                          static_cast<float>(std::cos(polar)),
                          static_cast<float>(std::sin(polar) * std::sin(azimuth))};
      mesh.positions.insert(mesh.positions.end(), p, p + 3);
      mesh.normals.insert(mesh.normals.end(), p, p + 3);
    }
  }
  const auto vertex = [slices](int i, int j) { return static_cast<std::uint32_t>(j * (slices + 1) + i); };
  for (int j = 0; j < stacks; ++j)
    for (int i = 0; i < slices; ++i) {
      // Quad (i, j)-(i+1, j+1) as two triangles, wound counter-clockwise seen from outside.
      const std::uint32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1),
                          d = vertex(i, j + 1);
      if (j > 0) mesh.triangles.insert(mesh.triangles.end(), {a, b, d});               // not at the north pole
      if (j < stacks - 1) mesh.triangles.insert(mesh.triangles.end(), {b, c, d});      // not at the south pole
    }
  return mesh;
}

int sphere_slices(float radius_px, float max_error_px) {
  constexpr int kFewest = 12, kMost = 128;  // 12: still round at a few pixels; 128: 0.25 px at 1300 px
  if (!(radius_px > max_error_px)) return kFewest;        // tiny (or NaN): any polygon will do
  if (!std::isfinite(radius_px)) return kMost;             // the eye inside or at the sphere
  const double half_angle = std::acos(1.0 - static_cast<double>(max_error_px) / radius_px);
  const int slices = static_cast<int>(std::ceil(3.14159265358979323846 / half_angle));
  return std::clamp((slices + 3) / 4 * 4, kFewest, kMost);
}

}  // namespace clothsim
