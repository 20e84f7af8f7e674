// What the renderer derives from a RenderFrame before and after any GL: the frame checked,
// the camera and key light, the lights and colour conventions, and the text overlay.
// Plain C++ (no GL), so it is tested on its own.
#pragma once

#include "render/gl/gl_math.h"
#include "image.h"
#include "view/render_frame.h"

namespace clothsim::render {

using gl::Mat4;
using gl::Vec3;

// The lights, linear RGB. One definition for the shaders (uniforms) and for the CPU-side
// ground colours, so a lit cloth and a lit ground agree. An upward surface facing the key
// light receives about 1: it shows the colour the frame gives. RenderFrame colours are taken
// as display values (gamma 2), squared to linear for lighting.
constexpr Vec3 kKeyLight{0.70f, 0.69f, 0.66f};    // directional key light, slightly warm
constexpr Vec3 kSkyLight{0.40f, 0.43f, 0.48f};    // ambient from above, cool
constexpr Vec3 kBounceLight{0.22f, 0.20f, 0.18f};  // ambient from below, warm

inline Vec3 mul(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
Vec3 display(Vec3 linear);  // gamma 2, as the shaders' to_display()
inline Vec3 to_vec3(const Rgb& c) { return {c[0], c[1], c[2]}; }
inline Vec3 linear(const Rgb& c) { return {c[0] * c[0], c[1] * c[1], c[2] * c[2]}; }

// Everything derived from RenderFrame::camera for one frame.
struct View {
  Mat4 view_proj;                 // world -> clip
  Vec3 eye, right, up, forward;   // camera position and basis, world
  float tan_half_x = 1.f, tan_half_y = 1.f;
  float distance = 1.f;  // eye to target, m: the scene's scale for near/far, fog, ground extent
  Vec3 light_dir;        // unit, towards the key light; always above the horizon
};
View make_view(const RenderFrame& frame);

// A sphere's radius on screen, in pixels, where its outline is widest: along the line from the
// image centre through it, where perspective stretches it most (half of tan(theta + alpha) -
// tan(theta - alpha) for a sphere at angle theta off the view axis and angular radius alpha).
// Infinite when it reaches the plane through the eye, or holds the eye. For sphere_slices().
float sphere_radius_px(Vec3 center, float radius, const View& view, int height);

// The same for the shadow a sphere casts on the ground (RenderFrame::ground_height) down the
// key light: an ellipse r by r / light_dir.y about the point under the centre, measured as a
// sphere of the larger radius there (at least as large on screen as the ellipse).
float sphere_shadow_radius_px(Vec3 center, float radius, float ground_height, const View& view, int height);

// A rectangle of pixels in GL's bottom-up coordinates, half-open: [x0, x1) x [y0, y1).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

// Where the frame draws over the backdrop: cloth, spheres and (with a ground and shadows)
// their shadows, widened by `margin` pixels for edges, lines and particle sprites; the whole
// image when something reaches behind the camera. Nothing is drawn outside it, so only this
// rectangle need be cleared, resolved and read back: the rest of the image is backdrop.
PixelRect drawn_region(const RenderFrame& frame, const View& view, int margin);

// Throws RenderError naming what is wrong: a size outside 1..max_size, arrays whose lengths
// disagree (cloth_field: none or one value per particle), indices past the particles, a sphere
// without a positive radius, a colour scale with lo >= hi (or lo <= 0 on a log scale), an
// inset with unequal series or an empty axis range.
void validate_frame(const RenderFrame& frame, int max_size);

// What is drawn over the rendered picture, on the CPU: overlay lines top-left in white, the
// colour bar (a field-coloured cloth) at the right edge, the series inset bottom-right, the
// banner centred in red, all on dark backdrops, placed by layout_overlay (overlay_layout.h).
// Text scale text_scale_for_height(height) (text.h): cap height >= height / 30, so 1 up to
// 210 rows, 2 at 360, 4 at 720p, 6 at 1080p.
void draw_overlay(Image& image, const RenderFrame& frame);

}  // namespace clothsim::render
