// The automatic camera (`render.camera: auto`, `--camera auto`): a view that frames the cloth
// and the spheres from the scene's own extent, so the cloth fills the tile whatever its size.
//
// The eye looks at the centre of what it frames from the front, as the shipped scenes do
// (azimuth 0: from -z towards +z, the course's drape camera at (0, 2, -10)), raised by
// `elevation_deg` so a horizontal cloth is seen from above rather than edge-on; a positive
// azimuth swings the eye towards +x (the curtain's camera sits near azimuth 40).
//
// The fit is exact under perspective: every cloth point is projected, and each sphere's
// silhouette by its tangent planes through the eye, so the nearest and widest parts decide
// (a bounding sphere would leave the picture loose). The distance is then found by bisection
// (the projected extent shrinks monotonically with distance) so that the limiting dimension,
// width or height, is filled to `fill` of the view, and the aim is moved to centre the
// projected extent, which perspective makes asymmetric about the box's centre.
// Pure arithmetic: no Model, no GL.
#pragma once

#include <array>
#include <vector>

#include "render_frame.h"

namespace clothsim {

struct CameraFitOptions {
  float fov_deg = 45.f;        // vertical field of view, as RenderCamera
  float elevation_deg = 30.f;  // above the horizontal, clamped to [-85, 85]
  float azimuth_deg = 0.f;     // 0: from -z; positive: the eye towards +x
  float fill = 0.8f;           // share of the limiting half-extent (width or height) filled
};

// A camera whose view (at `aspect` = width / height) holds every point and sphere, filling
// `fill` of its limiting dimension. Degenerate input (no points, one point, a line along the
// view) still gives a finite camera, looking at them from a distance of about a metre or more.
RenderCamera fit_camera(const std::vector<std::array<float, 3>>& cloth_points,
                        const std::vector<RenderSphere>& spheres, float aspect,
                        const CameraFitOptions& options = {});

// The same for cloth positions as RenderFrame holds them, (3 x P) flat.
RenderCamera fit_camera(const std::vector<float>& cloth_positions, const std::vector<RenderSphere>& spheres,
                        float aspect, const CameraFitOptions& options = {});

}  // namespace clothsim
