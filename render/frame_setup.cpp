#include "frame_setup.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "color_bar.h"
#include "colormap.h"
#include "overlay_layout.h"
#include "renderer.h"
#include "series_inset.h"
#include "text.h"

namespace clothsim::render {

Vec3 display(Vec3 linear) {
  const auto g = [](float c) { return std::sqrt(std::clamp(c, 0.f, 1.f)); };
  return {g(linear.x), g(linear.y), g(linear.z)};
}

View make_view(const RenderFrame& frame) {
  const RenderCamera& c = frame.camera;
  View v;
  v.eye = gl::to_vec3(c.eye);
  const Vec3 target = gl::to_vec3(c.target);
  v.distance = std::max(gl::length(target - v.eye), 1e-3f);
  const Mat4 view = gl::look_at(v.eye, target, gl::to_vec3(c.up));
  v.right = {view.at(0, 0), view.at(0, 1), view.at(0, 2)};
  v.up = {view.at(1, 0), view.at(1, 1), view.at(1, 2)};
  v.forward = {-view.at(2, 0), -view.at(2, 1), -view.at(2, 2)};
  const float aspect = static_cast<float>(frame.width) / static_cast<float>(frame.height);
  v.tan_half_y = std::tan(c.fov_deg * 3.14159265f / 360.f);
  v.tan_half_x = v.tan_half_y * aspect;
  v.view_proj = gl::perspective(c.fov_deg, aspect, 0.01f * v.distance, 50.f * v.distance) * view;
  // Key light above, over the viewer's left shoulder, whatever way the camera looks, so
  // shadows fall behind and to the right of what casts them.
  Vec3 back = {-v.forward.x, 0.f, -v.forward.z};
  Vec3 left = {-v.right.x, 0.f, -v.right.z};
  if (gl::length(back) < 1e-3f) back = {0.f, 0.f, -1.f};  // looking straight down
  if (gl::length(left) < 1e-3f) left = {1.f, 0.f, 0.f};
  v.light_dir = gl::normalize(Vec3{0.f, 1.f, 0.f} + gl::normalize(left) * 0.45f + gl::normalize(back) * 0.35f);
  return v;
}

float sphere_radius_px(Vec3 center, float radius, const View& view, int height) {
  constexpr float kInfinite = std::numeric_limits<float>::infinity();
  const Vec3 to_center = center - view.eye;
  const float d = gl::length(to_center);
  if (!(d > radius)) return kInfinite;
  const float alpha = std::asin(radius / d);
  const float theta = std::acos(std::clamp(gl::dot(to_center, view.forward) / d, -1.f, 1.f));
  if (theta + alpha >= 0.5f * 3.14159265f) return kInfinite;
  const float half_extent = 0.5f * (std::tan(theta + alpha) - std::tan(theta - alpha));  // 1 m ahead of the eye
  return half_extent * 0.5f * static_cast<float>(height) / view.tan_half_y;
}

float sphere_shadow_radius_px(Vec3 center, float radius, float ground_height, const View& view, int height) {
  const float drop = std::max(center.y - ground_height, 0.f) / view.light_dir.y;  // as the shadow vertex shader
  const Vec3 under = {center.x - view.light_dir.x * drop, ground_height, center.z - view.light_dir.z * drop};
  return sphere_radius_px(under, radius / view.light_dir.y, view, height);
}

PixelRect drawn_region(const RenderFrame& frame, const View& view, int margin) {
  const PixelRect whole{0, 0, frame.width, frame.height};
  float lo_x = 1e30f, lo_y = 1e30f, hi_x = -1e30f, hi_y = -1e30f;
  bool behind = false;
  const bool shadows = frame.has_ground && frame.shadows;
  const auto add = [&](Vec3 p) {
    const Mat4& m = view.view_proj;
    const float w = m.at(3, 0) * p.x + m.at(3, 1) * p.y + m.at(3, 2) * p.z + m.at(3, 3);
    if (w < 0.01f * view.distance) {  // at or behind the near plane: its projection is unbounded
      behind = true;
      return;
    }
    const float x = (m.at(0, 0) * p.x + m.at(0, 1) * p.y + m.at(0, 2) * p.z + m.at(0, 3)) / w;
    const float y = (m.at(1, 0) * p.x + m.at(1, 1) * p.y + m.at(1, 2) * p.z + m.at(1, 3)) / w;
    lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x);
    lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
  };
  const auto add_with_shadow = [&](Vec3 p) {
    add(p);
    if (shadows)  // as the shadow vertex shader: down the light ray onto the ground
      add({p.x - view.light_dir.x * std::max(p.y - frame.ground_height, 0.f) / view.light_dir.y,
           frame.ground_height,
           p.z - view.light_dir.z * std::max(p.y - frame.ground_height, 0.f) / view.light_dir.y});
  };
  const auto& x = frame.cloth_positions;
  for (std::size_t i = 0; i + 2 < x.size(); i += 3) add_with_shadow({x[i], x[i + 1], x[i + 2]});
  for (const RenderSphere& s : frame.spheres)  // the corners of its bounding cube: a convex hull
    for (int corner = 0; corner < 8; ++corner)
      add_with_shadow({s.center[0] + ((corner & 1) ? s.radius : -s.radius),
                       s.center[1] + ((corner & 2) ? s.radius : -s.radius),
                       s.center[2] + ((corner & 4) ? s.radius : -s.radius)});
  if (behind) return whole;
  if (hi_x < lo_x) return PixelRect{};  // nothing drawn
  const auto to_pixels = [](float ndc, int size) { return (ndc * 0.5f + 0.5f) * static_cast<float>(size); };
  const auto clamp = [](float v, int size) {
    return static_cast<int>(std::clamp(v, 0.f, static_cast<float>(size)));
  };
  PixelRect r;
  r.x0 = clamp(std::floor(to_pixels(lo_x, frame.width)) - static_cast<float>(margin), frame.width);
  r.x1 = clamp(std::ceil(to_pixels(hi_x, frame.width)) + static_cast<float>(margin), frame.width);
  r.y0 = clamp(std::floor(to_pixels(lo_y, frame.height)) - static_cast<float>(margin), frame.height);
  r.y1 = clamp(std::ceil(to_pixels(hi_y, frame.height)) + static_cast<float>(margin), frame.height);
  return r;
}

void validate_frame(const RenderFrame& f, int max_size) {
  const auto fail = [](const std::string& what) { throw RenderError("RenderFrame: " + what); };
  if (f.width < 1 || f.height < 1 || f.width > max_size || f.height > max_size)
    throw RenderError("image size " + std::to_string(f.width) + "x" + std::to_string(f.height) +
                      " is outside 1.." + std::to_string(max_size) + " pixels per side");
  if (f.cloth_positions.size() % 3 != 0) fail("cloth_positions is not a list of 3-vectors");
  const std::size_t particles = f.cloth_positions.size() / 3;
  if (f.cloth_normals.size() != f.cloth_positions.size())
    fail("cloth_normals has " + std::to_string(f.cloth_normals.size()) + " values, expected " +
         std::to_string(f.cloth_positions.size()));
  if (f.cloth_uv.size() != 2 * particles)
    fail("cloth_uv has " + std::to_string(f.cloth_uv.size()) + " values, expected " +
         std::to_string(2 * particles));
  if (f.cloth_triangles.size() % 3 != 0) fail("cloth_triangles is not a list of triangles");
  for (std::uint32_t i : f.cloth_triangles)
    if (i >= particles) fail("cloth_triangles refers to particle " + std::to_string(i) + " of " + std::to_string(particles));
  if (f.spring_lines.size() % 2 != 0) fail("spring_lines is not a list of pairs");
  for (std::uint32_t i : f.spring_lines)
    if (i >= particles) fail("spring_lines refers to particle " + std::to_string(i) + " of " + std::to_string(particles));
  if (f.spring_types.size() != f.spring_lines.size() / 2)
    fail("spring_types has " + std::to_string(f.spring_types.size()) + " entries for " +
         std::to_string(f.spring_lines.size() / 2) + " lines");
  for (const RenderSphere& s : f.spheres)
    if (!(s.radius > 0.f)) fail("a sphere has radius " + std::to_string(s.radius));
  const auto number = [](float v) { return short_number(v); };
  if (!f.cloth_field.empty()) {
    if (f.cloth_field.size() != particles)
      fail("cloth_field has " + std::to_string(f.cloth_field.size()) + " values, expected " +
           std::to_string(particles) + " (one per particle) or none");
    const ColorScale& c = f.color_scale;
    if (!std::isfinite(c.lo) || !std::isfinite(c.hi) || !(c.lo < c.hi))
      fail("color_scale runs from " + number(c.lo) + " to " + number(c.hi) + ": lo must be below hi, both finite");
    if (c.log && !(c.lo > 0.f))
      fail("color_scale is logarithmic but lo is " + number(c.lo) + ": both ends must be above 0");
  }
  if (f.inset.show) {
    const SeriesInset& in = f.inset;
    if (in.t.size() != in.value.size())
      fail("inset has " + std::to_string(in.t.size()) + " times and " + std::to_string(in.value.size()) + " values");
    if (!std::isfinite(in.t_lo) || !std::isfinite(in.t_hi) || !(in.t_lo < in.t_hi))
      fail("inset time axis runs from " + number(in.t_lo) + " to " + number(in.t_hi) + ": t_lo must be below t_hi");
    if (!std::isfinite(in.v_lo) || !std::isfinite(in.v_hi) || !(in.v_lo < in.v_hi))
      fail("inset value axis runs from " + number(in.v_lo) + " to " + number(in.v_hi) + ": v_lo must be below v_hi");
  }
}


// Placed by layout_overlay (overlay_layout.h); the banner last, over everything.
void draw_overlay(Image& image, const RenderFrame& frame) {
  const OverlayLayout layout = layout_overlay(frame, image.width, image.height);
  draw_color_bar(image, frame.color_scale, layout);  // each draws nothing when it has no box
  draw_series_inset(image, frame.inset, layout);
  const int scale = layout.scale, margin = layout.margin;
  if (!layout.lines.empty()) draw_text_block(image, margin, margin, layout.lines, {255, 255, 255, 255}, scale);
  if (!layout.banner_lines.empty()) {  // one backdrop for its lines, each centred on it
    const ImageBox& b = layout.banner;
    const int s = layout.banner_scale, line_h = text_glyph_height() * s;
    darken_rect(image, b.x - 2 * s, b.y - 2 * s, b.right() + 2 * s, b.bottom() + s);
    for (std::size_t i = 0; i < layout.banner_lines.size(); ++i) {
      const std::string& line = layout.banner_lines[i];
      draw_text(image, b.x + (b.w - text_width(line, s)) / 2, b.y + static_cast<int>(i) * line_h, line,
                {255, 72, 60, 255}, s, /*backdrop=*/false);
    }
  }
}

}  // namespace clothsim::render
