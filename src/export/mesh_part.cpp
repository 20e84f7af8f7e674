#include "export/mesh_part.h"

#include <cmath>

#include "view/vertex_fields.h"

namespace clothsim {
namespace {

VertexField velocity_field(const State& bodies, int first, int count) {
  VertexField f{"velocity", 3, {}};
  f.values.reserve(3 * static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) f.values.push_back(static_cast<float>(bodies.v(k, first)));
  return f;
}

// A UV sphere of unit radius: the two poles, then (rings - 1) rings of `segments` vertices.
struct UnitSphere {
  std::vector<double> points;
  std::vector<std::uint32_t> triangles;
  UnitSphere() {
    const double pi = std::acos(-1.0);
    points = {0, 0, 1, 0, 0, -1};
    for (int r = 1; r < kSphereRings; ++r)
      for (int s = 0; s < kSphereSegments; ++s) {
        const double theta = pi * r / kSphereRings, phi = 2 * pi * s / kSphereSegments;
        points.insert(points.end(), {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
      }
    const auto ring = [](int r, int s) { return static_cast<std::uint32_t>(2 + (r - 1) * kSphereSegments + s % kSphereSegments); };
    for (int s = 0; s < kSphereSegments; ++s) {
      triangles.insert(triangles.end(), {0u, ring(1, s), ring(1, s + 1)});
      triangles.insert(triangles.end(), {1u, ring(kSphereRings - 1, s + 1), ring(kSphereRings - 1, s)});
      for (int r = 1; r + 1 < kSphereRings; ++r)
        triangles.insert(triangles.end(), {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  }
};

}  // namespace

MeshPart cloth_part(const Model& model, const State& bodies, const std::vector<float>* error) {
  MeshPart part;
  part.name = "cloth";
  const int n = model.num_particles;
  part.points.reserve(3 * static_cast<std::size_t>(n));
  for (int p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) part.points.push_back(static_cast<float>(bodies.x(k, p)));
  part.triangles = model.triangles;
  VertexField velocity{"velocity", 3, {}};
  velocity.values.reserve(part.points.size());
  for (int p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) velocity.values.push_back(static_cast<float>(bodies.v(k, p)));
  part.fields.push_back(std::move(velocity));
  part.fields.push_back({"speed", 1, vertex_speed(model, bodies)});
  part.fields.push_back({"strain", 1, vertex_strain(model, bodies)});
  if (error) part.fields.push_back({"error", 1, *error});
  return part;
}

MeshPart sphere_part(const Model& model, const State& bodies, int s) {
  static const UnitSphere unit;
  const int body = model.sphere_body(s);
  const double r = model.sphere_radius[static_cast<std::size_t>(s)];
  MeshPart part;
  part.name = "sphere" + std::to_string(s);
  part.points.reserve(unit.points.size());
  for (std::size_t i = 0; i < unit.points.size(); ++i)
    part.points.push_back(static_cast<float>(bodies.x(static_cast<Eigen::Index>(i % 3), body) + r * unit.points[i]));
  part.triangles = unit.triangles;
  part.fields.push_back(velocity_field(bodies, body, static_cast<int>(unit.points.size() / 3)));
  return part;
}

}  // namespace clothsim
