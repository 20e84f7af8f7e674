// RenderFrames built by hand, independent of the engine: a sheet of cloth (flat, or draped
// over a sphere by a closed-form shape), spheres and a ground, the error scale and the energy
// inset the overlay tests draw, and the grey picture they draw on. Deterministic inputs for the
// renderer's unit tests and benchmarks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "render/image.h"
#include "view/render_frame.h"

namespace clothsim::testing {

// An opaque picture of one grey level: what overlays are drawn over in their tests.
inline Image grey_image(int w, int h, std::uint8_t level = 128) {
  Image image(w, h);
  for (std::size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = (i % 4 == 3) ? 255 : level;
  return image;
}

// The error colouring's scale as compare draws it, 1e-6 to 0.1 m (the field itself is the
// test's).
inline void set_error_scale(RenderFrame& frame) {
  frame.color_scale.lo = 1e-6f;
  frame.color_scale.hi = 1e-1f;
  frame.color_scale.label = "error [m]";
}

// The energy inset shown, on axes [0, t_hi] s x [v_lo, v_hi] J (its series are the test's).
inline void show_energy_inset(RenderFrame& frame, float t_hi, float v_lo, float v_hi) {
  frame.inset.show = true;
  frame.inset.label = "E-E(0) [J]";
  frame.inset.t_lo = 0.f;
  frame.inset.t_hi = t_hi;
  frame.inset.v_lo = v_lo;
  frame.inset.v_hi = v_hi;
}

// An nx x ny particle sheet over [-size/2, size/2]^2 in x and z, its height given by
// height(x, z). Vertex normals are area-weighted triangle normals; triangles are
// counter-clockwise seen from +y, so the front (cloth_front colour) faces up.
template <class HeightFn>
void add_sheet(RenderFrame& frame, int nx, int ny, float size, HeightFn height) {
  frame.cloth_positions.clear();
  frame.cloth_uv.clear();
  frame.cloth_triangles.clear();
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float u = static_cast<float>(i) / static_cast<float>(nx - 1);
      const float v = static_cast<float>(j) / static_cast<float>(ny - 1);
      const float x = (u - 0.5f) * size, z = (v - 0.5f) * size;
      frame.cloth_positions.insert(frame.cloth_positions.end(), {x, height(x, z), z});
      frame.cloth_uv.insert(frame.cloth_uv.end(), {u, v});
    }
  const auto id = [nx](int i, int j) { return static_cast<std::uint32_t>(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      frame.cloth_triangles.insert(frame.cloth_triangles.end(), {id(i, j), id(i, j + 1), id(i + 1, j)});
      frame.cloth_triangles.insert(frame.cloth_triangles.end(), {id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  // Area-weighted normals: the unnormalised cross product of each triangle, summed per vertex.
  const std::vector<float>& x = frame.cloth_positions;
  std::vector<float> n(x.size(), 0.f);
  for (std::size_t t = 0; t < frame.cloth_triangles.size(); t += 3) {
    const std::uint32_t a = frame.cloth_triangles[t], b = frame.cloth_triangles[t + 1], c = frame.cloth_triangles[t + 2];
    const float e1[3] = {x[3 * b] - x[3 * a], x[3 * b + 1] - x[3 * a + 1], x[3 * b + 2] - x[3 * a + 2]};
    const float e2[3] = {x[3 * c] - x[3 * a], x[3 * c + 1] - x[3 * a + 1], x[3 * c + 2] - x[3 * a + 2]};
    const float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (std::uint32_t v : {a, b, c})
      for (int k = 0; k < 3; ++k) n[3 * v + k] += cr[k];
  }
  for (std::size_t v = 0; v < n.size(); v += 3) {
    const float len = std::sqrt(n[v] * n[v] + n[v + 1] * n[v + 1] + n[v + 2] * n[v + 2]);
    for (int k = 0; k < 3; ++k) n[v + k] = len > 0.f ? n[v + k] / len : (k == 1 ? 1.f : 0.f);
  }
  frame.cloth_normals = n;
}

// Structural springs of the sheet (type 0) plus its shear diagonals (type 1), as lines.
inline void add_grid_springs(RenderFrame& frame, int nx, int ny) {
  const auto id = [nx](int i, int j) { return static_cast<std::uint32_t>(j * nx + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) { frame.spring_lines.insert(frame.spring_lines.end(), {id(i, j), id(i + 1, j)}); frame.spring_types.push_back(0); }
      if (j + 1 < ny) { frame.spring_lines.insert(frame.spring_lines.end(), {id(i, j), id(i, j + 1)}); frame.spring_types.push_back(0); }
      if (i + 1 < nx && j + 1 < ny) { frame.spring_lines.insert(frame.spring_lines.end(), {id(i, j), id(i + 1, j + 1)}); frame.spring_types.push_back(1); }
    }
}

// The course's drape: a 4 m sheet of nx x nx particles over a unit sphere at the origin,
// ground at y = -2, default camera. The cloth shape is closed-form (a cap on the sphere,
// then a skirt falling away), not simulated.
inline RenderFrame draped_sheet_frame(int width, int height, int nx = 25) {
  RenderFrame frame;
  frame.width = width;
  frame.height = height;
  add_sheet(frame, nx, nx, 4.f, [](float x, float z) {
    const float r = std::sqrt(x * x + z * z);
    if (r < 0.8f) return std::sqrt(1.f - r * r) + 0.03f;           // resting on the cap
    const float edge = std::sqrt(1.f - 0.64f) + 0.03f;
    return edge - 1.3f * (r - 0.8f) - 0.15f * std::sin(6.f * std::atan2(z, x)) * (r - 0.8f);  // folds
  });
  frame.spheres.push_back(RenderSphere{{0.f, 0.f, 0.f}, 1.f, {0.80f, 0.25f, 0.20f}});
  frame.has_ground = true;
  frame.ground_height = -2.f;
  return frame;
}

// A flat horizontal sheet of n x n particles at y = 0, 4 m across, seen from the default camera.
inline RenderFrame flat_sheet_frame(int width, int height, int n) {
  RenderFrame frame;
  frame.width = width;
  frame.height = height;
  add_sheet(frame, n, n, 4.f, [](float, float) { return 0.f; });
  frame.has_ground = true;
  frame.ground_height = -2.f;
  return frame;
}

}  // namespace clothsim::testing
