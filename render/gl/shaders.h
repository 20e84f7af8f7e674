// GLSL 330 core sources of the renderer's programs. Lit surfaces (cloth, spheres) share
// one Blinn-Phong chunk; the ground and sky (the backdrop, drawn once per camera) and the
// shadows are flat-cost shaders.
#pragma once

#include <string>

namespace clothsim::shaders {

// Surface vertex shader for cloth, spheres and ground: world position =
// u_placement.xyz + u_placement.w * a_position (a sphere is the unit sphere mesh placed by
// centre and radius; cloth and ground pass (0, 0, 0, 1)).
extern const std::string kSurfaceVertex;

// Two-sided; a box-filtered checker from the grid uv, or with u_field the colormap texture
// looked up at the field's interpolated scale position (attribute 3).
extern const std::string kClothFragment;
extern const std::string kSphereFragment;  // smooth, glossy
extern const std::string kGroundFragment;  // anti-aliased minor/major grid, fog to the horizon

// Planar projected shadows (Blinn, "Me and my (fake) shadow", 1988): cloth and spheres
// flattened onto the ground along the light direction, written as translucent black.
extern const std::string kShadowVertex;
extern const std::string kShadowFragment;

// A full-screen triangle shading the sky (and, without ground, the floor-less backdrop)
// by the direction of each pixel's view ray.
extern const std::string kBackgroundVertex;
extern const std::string kBackgroundFragment;

// Flat-coloured lines (springs), and particles as point sprites shaded like small balls.
extern const std::string kFlatVertex;
extern const std::string kFlatFragment;

}  // namespace clothsim::shaders
