#include "camera_fit.h"

#include <algorithm>
#include <cmath>

namespace clothsim {

namespace {

struct V3 {
  double x = 0, y = 0, z = 0;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 normalize(V3 a) { return a * (1.0 / std::sqrt(dot(a, a))); }

// What is framed: points (radius 0) and spheres.
struct Item {
  V3 c;
  double r = 0;
};

// The view's basis as gl::look_at builds it from `forward` and up = +y.
struct Basis {
  V3 forward, right, up;
};

// Projected bounds in normalised device coordinates, [-1, 1] being the edges of the view.
struct Bounds {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  double reach() const { return std::max({-x0, x1, -y0, y1}); }  // the limiting dimension
};

// The slopes a / depth of the two lines through the eye tangent to a disc of radius r centred
// at (a, depth) in one plane: the silhouette of a sphere, as seen along one screen axis (the
// sphere's orthogonal projection onto the plane is a disc of the same radius). depth > r.
std::pair<double, double> tangent_slopes(double a, double depth, double r) {
  if (r <= 0) return {a / depth, a / depth};
  const double d2 = depth * depth - r * r;
  const double root = r * std::sqrt(std::max(a * a + d2, 0.0));
  return {(a * depth - root) / d2, (a * depth + root) / d2};
}

Bounds project(const std::vector<Item>& items, const Basis& b, V3 eye, double tan_x, double tan_y) {
  Bounds out;
  for (const Item& it : items) {
    const V3 d = it.c - eye;
    const double depth = dot(d, b.forward);
    const auto [x0, x1] = tangent_slopes(dot(d, b.right), depth, it.r);
    const auto [y0, y1] = tangent_slopes(dot(d, b.up), depth, it.r);
    out.x0 = std::min(out.x0, x0 / tan_x), out.x1 = std::max(out.x1, x1 / tan_x);
    out.y0 = std::min(out.y0, y0 / tan_y), out.y1 = std::max(out.y1, y1 / tan_y);
  }
  return out;
}

}  // namespace

RenderCamera fit_camera(const std::vector<std::array<float, 3>>& cloth_points, const std::vector<RenderSphere>& spheres,
                        float aspect, const CameraFitOptions& options) {
  std::vector<Item> items;
  V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto add = [&](V3 c, double r) {
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(r)) return;
    items.push_back({c, std::max(r, 0.0)});
    lo = {std::min(lo.x, c.x - r), std::min(lo.y, c.y - r), std::min(lo.z, c.z - r)};
    hi = {std::max(hi.x, c.x + r), std::max(hi.y, c.y + r), std::max(hi.z, c.z + r)};
  };
  for (const auto& p : cloth_points) add({p[0], p[1], p[2]}, 0.0);
  for (const RenderSphere& s : spheres) add({s.center[0], s.center[1], s.center[2]}, s.radius);
  if (items.empty()) add({0, 0, 0}, 0.0);
  V3 target = (lo + hi) * 0.5;
  double size = std::sqrt(dot(hi - lo, hi - lo));
  if (size < 1e-6) {  // one point: framed as a ball of a metre, so the distance means something
    items.push_back({target, 0.5});
    size = 1.0;
  }

  const double pi = 3.14159265358979323846;
  const double elevation = std::clamp(static_cast<double>(options.elevation_deg), -85.0, 85.0) * pi / 180.0;
  const double azimuth = static_cast<double>(options.azimuth_deg) * pi / 180.0;
  Basis b;
  b.forward = {-std::sin(azimuth) * std::cos(elevation), -std::sin(elevation), std::cos(azimuth) * std::cos(elevation)};
  b.right = normalize(cross(b.forward, {0, 1, 0}));
  b.up = cross(b.right, b.forward);
  const double tan_y = std::tan(std::clamp(static_cast<double>(options.fov_deg), 1.0, 170.0) * pi / 360.0);
  const double tan_x = tan_y * std::max(static_cast<double>(aspect), 1e-3);
  const double fill = std::clamp(static_cast<double>(options.fill), 0.05, 1.0);

  // The distance from the target at which the limiting dimension is filled to `fill`.
  const auto distance_for = [&](V3 aim) {
    double nearest = 0;  // the eye stays in front of everything, with a little room
    for (const Item& it : items) nearest = std::max(nearest, it.r - dot(it.c - aim, b.forward));
    const double d_min = nearest + 0.05 * size;
    const auto reach = [&](double d) { return project(items, b, aim - b.forward * d, tan_x, tan_y).reach(); };
    if (reach(d_min) <= fill) return d_min;  // degenerate (a line along the view): as near as allowed
    double d_lo = d_min, d_hi = d_min + size;
    for (int i = 0; i < 200 && reach(d_hi) > fill; ++i) d_hi *= 2.0;
    for (int i = 0; i < 60; ++i) {  // the extent shrinks as the eye backs away: bisect
      const double mid = 0.5 * (d_lo + d_hi);
      (reach(mid) > fill ? d_lo : d_hi) = mid;
    }
    return d_hi;
  };

  // Perspective makes the near side project larger: move the aim across the view until the
  // projected extent is centred (the shift at the target's depth; a few rounds converge).
  double distance = distance_for(target);
  for (int round = 0; round < 8; ++round) {
    const Bounds bounds = project(items, b, target - b.forward * distance, tan_x, tan_y);
    const double mid_x = 0.5 * (bounds.x0 + bounds.x1), mid_y = 0.5 * (bounds.y0 + bounds.y1);
    target = target + b.right * (mid_x * tan_x * distance) + b.up * (mid_y * tan_y * distance);
    distance = distance_for(target);
  }

  const V3 eye = target - b.forward * distance;
  RenderCamera camera;
  camera.eye = {static_cast<float>(eye.x), static_cast<float>(eye.y), static_cast<float>(eye.z)};
  camera.target = {static_cast<float>(target.x), static_cast<float>(target.y), static_cast<float>(target.z)};
  camera.up = {0.f, 1.f, 0.f};
  camera.fov_deg = static_cast<float>(std::clamp(static_cast<double>(options.fov_deg), 1.0, 170.0));
  return camera;
}

RenderCamera fit_camera(const std::vector<float>& cloth_positions, const std::vector<RenderSphere>& spheres,
                        float aspect, const CameraFitOptions& options) {
  std::vector<std::array<float, 3>> points(cloth_positions.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = {cloth_positions[3 * i], cloth_positions[3 * i + 1], cloth_positions[3 * i + 2]};
  return fit_camera(points, spheres, aspect, options);
}

}  // namespace clothsim
