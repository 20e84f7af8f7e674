#include "snapshot.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "camera_fit.h"

namespace clothsim {
namespace {

std::array<float, 3> to_f3(const Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

// Area-weighted vertex normals: the sum of the (unnormalised) face normals around a vertex
// weights each face by its area, which keeps a stretched cell from dominating its neighbours.
std::vector<float> vertex_normals(const Model& model, const State& state) {
  const int P = model.num_particles;
  Eigen::Matrix3Xd n = Eigen::Matrix3Xd::Zero(3, P);
  const auto& tri = model.triangles;
  for (std::size_t k = 0; k + 2 < tri.size(); k += 3) {
    const Vec3 a = state.x.col(tri[k]), b = state.x.col(tri[k + 1]), c = state.x.col(tri[k + 2]);
    const Vec3 face = (b - a).cross(c - a);
    for (int e = 0; e < 3; ++e) n.col(tri[k + e]) += face;
  }
  std::vector<float> out(3 * static_cast<std::size_t>(P));
  for (int p = 0; p < P; ++p) {
    const double len = n.col(p).norm();
    // A chain or a single spring has no faces: give it the plane's normal.
    const Vec3 unit = len > 0.0 ? Vec3(n.col(p) / len) : Vec3::UnitY();
    for (int d = 0; d < 3; ++d) out[3 * p + d] = static_cast<float>(unit[d]);
  }
  return out;
}

}  // namespace

RenderFrame make_render_frame(const Model& model, const State& state, const RenderDef& r) {
  RenderFrame f;
  f.width = r.width;
  f.height = r.height;
  f.samples = r.samples;
  f.camera.eye = to_f3(r.camera.eye);
  f.camera.target = to_f3(r.camera.target);
  f.camera.up = to_f3(r.camera.up);
  f.camera.fov_deg = static_cast<float>(r.camera.fov);

  const int P = model.num_particles;
  f.cloth_positions.resize(3 * static_cast<std::size_t>(P));
  f.cloth_uv.resize(2 * static_cast<std::size_t>(P));
  for (int p = 0; p < P; ++p) {
    for (int d = 0; d < 3; ++d) f.cloth_positions[3 * p + d] = static_cast<float>(state.x(d, p));
    const int i = p % model.grid_nx, j = p / model.grid_nx;
    f.cloth_uv[2 * p] = model.grid_nx > 1 ? float(i) / float(model.grid_nx - 1) : 0.f;
    f.cloth_uv[2 * p + 1] = model.grid_ny > 1 ? float(j) / float(model.grid_ny - 1) : 0.f;
  }
  f.cloth_normals = vertex_normals(model, state);
  f.cloth_triangles = model.triangles;
  // About one checker square per 3 x 3 particles, so stretching shows at any resolution.
  f.checker_cells_u = std::max(1, (model.grid_nx - 1 + 2) / 3);
  f.checker_cells_v = std::max(1, (model.grid_ny - 1 + 2) / 3);

  // Without triangles (a chain, a spring) the springs are all there is to see: draw them.
  if (r.draw_springs || model.triangles.empty()) {
    const Springs& s = model.springs;
    for (std::size_t k = 0; k < s.size(); ++k) {
      f.spring_lines.push_back(static_cast<std::uint32_t>(s.a[k]));
      f.spring_lines.push_back(static_cast<std::uint32_t>(s.b[k]));
      f.spring_types.push_back(static_cast<std::uint8_t>(s.type[k]));
    }
  }
  f.draw_particles = r.draw_particles || model.triangles.empty();

  for (int s = 0; s < model.num_spheres; ++s) {
    RenderSphere sphere;
    sphere.center = to_f3(state.x.col(model.sphere_body(s)));
    sphere.radius = static_cast<float>(model.sphere_radius[s]);
    if (!model.sphere_kinematic[s]) sphere.color = {0.25f, 0.65f, 0.35f};  // dynamic: green
    f.spheres.push_back(sphere);
  }
  f.has_ground = model.has_ground;
  if (model.has_ground) f.ground_height = static_cast<float>(model.ground.height);
  return f;
}

RenderCamera fit_scene_camera(const Model& model, const RenderDef& look, double aspect) {
  const RenderFrame at_rest = make_render_frame(model, initial_state(model), look);
  CameraFitOptions options;
  options.fov_deg = at_rest.camera.fov_deg;  // the scene's lens, aimed anew
  options.elevation_deg = 40.f;  // CompareLook.TheDefaultClipsClothCoversAQuarterOfEachTile
  return fit_camera(at_rest.cloth_positions, at_rest.spheres, static_cast<float>(aspect), options);
}

}  // namespace clothsim
