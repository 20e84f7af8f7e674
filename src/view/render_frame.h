// RenderFrame: the snapshot the renderer draws, and all it may know of a scene.
// Its geometry filled on the engine side by make_render_frame() (snapshot.h), its words (overlay
// lines, banner) by the tools that show it (src/clip/frames/overlay_text.h); read by render/.
// Plain values only: no Eigen, no GL, so render/ and the engine share nothing else.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace clothsim {

using Rgb = std::array<float, 3>;  // display colour 0..1: a surface facing the light shows it as given

struct RenderCamera {
  std::array<float, 3> eye{0.f, 2.f, -10.f};
  std::array<float, 3> target{0.f, 0.f, 0.f};
  std::array<float, 3> up{0.f, 1.f, 0.f};
  float fov_deg = 45.f;  // vertical field of view
};

struct RenderSphere {
  std::array<float, 3> center{0.f, 0.f, 0.f};
  float radius = 1.f;
  Rgb color{0.80f, 0.25f, 0.20f};
};

// How a per-particle value becomes a colour (RenderFrame::cloth_field): value -> position in
// [0, 1] (log10 between lo and hi on a log scale, linear otherwise; clamped) -> the colormap
// of render/colormap.h (viridis: dark purple at lo, yellow at hi).
struct ColorScale {
  float lo = 1e-6f, hi = 1e-1f;   // the field's units; lo < hi, both > 0 on a log scale
  bool log = true;                // on a log scale values <= 0 or not finite show as lo
  std::string label;              // with units, drawn on the colour bar: "error [m]", "strain"
  bool show_bar = true;           // the colour bar at the right edge (when cloth_field is set)
};

// A small graph of one quantity over time drawn in a corner of the frame (the energy inset).
// The axes come from the caller, who shares them across the tiles of a clip so they compare.
struct SeriesInset {
  bool show = false;
  std::vector<float> t, value;    // (K) samples up to the frame's time, t increasing; s, units
  float t_lo = 0.f, t_hi = 1.f;   // s: the horizontal axis; t_lo < t_hi
  float v_lo = 0.f, v_hi = 1.f;   // the vertical axis; v_lo < v_hi; values outside are clamped
  std::string label;              // with units: "total energy [J]"
};

// MSAA samples where nothing says otherwise: what `run` draws with, what an FXAA frame's
// backdrop keeps, and what render.msaa defaults to.
inline constexpr int kDefaultMsaaSamples = 4;

struct RenderFrame {
  int width = 1280, height = 720;  // pixels of the image to produce
  int samples = kDefaultMsaaSamples;  // MSAA samples (1 = none)
  bool fxaa = false;               // then smooth the drawn edges on the CPU (render/fxaa.h); the
                                   // backdrop, drawn once per camera, keeps 4 samples regardless
  RenderCamera camera;
  Rgb background{0.93f, 0.94f, 0.96f};

  // Cloth: a triangle mesh over the particle grid.
  std::vector<float> cloth_positions;        // (3 x P) m
  std::vector<float> cloth_normals;          // (3 x P) unit, area-weighted vertex normals
  std::vector<float> cloth_uv;               // (2 x P) grid coordinates in [0,1], for the checker
  std::vector<std::uint32_t> cloth_triangles;  // (3 x T) indices into the particle arrays
  int checker_cells_u = 8, checker_cells_v = 8;  // checker squares across the cloth
  Rgb cloth_front{0.20f, 0.45f, 0.85f};
  Rgb cloth_back{0.95f, 0.70f, 0.20f};
  // Colour by a per-particle field instead of the checker (both faces, lit as the checker is).
  std::vector<float> cloth_field;            // (P) in color_scale's units; empty: the checker
  ColorScale color_scale;

  // Optional spring / particle overlay (the course's UI toggles).
  std::vector<std::uint32_t> spring_lines;   // (2 x L) particle index pairs to draw as lines
  std::vector<std::uint8_t> spring_types;    // (L) 0 structural, 1 shear, 2 bend: line colour
  bool draw_particles = false;

  std::vector<RenderSphere> spheres;

  bool has_ground = false;
  float ground_height = 0.f;                 // plane y = ground_height
  Rgb ground_color{0.82f, 0.82f, 0.80f};
  float ground_grid_spacing = 0.5f;          // m between grid lines
  bool shadows = true;                       // shadow of cloth and spheres on the ground

  // Text drawn over the image with the built-in bitmap font (deterministic across machines).
  std::vector<std::string> overlay_lines;    // top-left, one per line (scene, integrator, dt, t)
  // The red banner over everything, centred (DIVERGED, NOT CONVERGED), as phrases, the most
  // important first: {"DIVERGED", "at t = 1.234 s", "(step 12340)"}. On one line, joined by
  // spaces, where it fits; else on two lines broken between phrases, never inside one; where
  // two lines cannot hold them all even at the smallest text, or would cover the overlay lines
  // where fewer would not, the last phrases are left off, never the first two
  // (render/overlay_layout.h). Empty: no banner.
  std::vector<std::string> banner;
  SeriesInset inset;                         // bottom-right when inset.show
};

}  // namespace clothsim
