#include "shaders.h"

namespace clothsim::shaders {

namespace {

const char* const kVersion = "#version 330 core\n";

// Shared by cloth and spheres. Colour uniforms arrive in display space (what a surface facing
// the light shows); lighting happens on linear values (to_linear), to_display() applies gamma once.
const char* const kLighting = R"(
in vec3 v_world;
in vec3 v_normal;
in vec2 v_uv;
out vec4 frag_color;

uniform vec3 u_eye;              // camera position, world
uniform vec3 u_light_dir;        // unit vector towards the (directional) key light
uniform vec3 u_key;              // key light colour x intensity, linear
uniform vec3 u_sky, u_bounce;    // hemisphere ambient: from above, from below, linear

// Blinn-Phong under a hemisphere ambient: cool sky light from above, warm bounce from below,
// plus the key light's diffuse and specular terms.
vec3 shade(vec3 albedo, vec3 n, float shininess, float specular) {
  vec3 v = normalize(u_eye - v_world);
  float n_dot_l = max(dot(n, u_light_dir), 0.0);
  vec3 ambient = mix(u_bounce, u_sky, 0.5 + 0.5 * n.y);
  vec3 h = normalize(u_light_dir + v);
  float spec = n_dot_l > 0.0 ? specular * pow(max(dot(n, h), 0.0), shininess) : 0.0;
  return albedo * (ambient + u_key * n_dot_l) + u_key * spec;
}

vec3 to_linear(vec3 display) { return display * display; }
// Gamma 2 (sqrt: one instruction, where pow(c, 1/2.2) costs a log and an exp per channel on llvmpipe).
vec4 to_display(vec3 linear) { return vec4(sqrt(clamp(linear, 0.0, 1.0)), 1.0); }
)";

}  // namespace

const std::string kSurfaceVertex = std::string(kVersion) + R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in float a_field;  // cloth: the field's place on its colour scale, 0..1
uniform mat4 u_view_proj;
uniform vec4 u_placement;   // xyz offset, w scale
uniform vec4 u_clip_plane;  // the ground: what lies below it is clipped (when enabled)
out vec3 v_world;
out vec3 v_normal;
out vec2 v_uv;
out float v_field;
void main() {
  v_world = u_placement.xyz + u_placement.w * a_position;  // model -> world
  v_normal = a_normal;                                      // uniform scale: normals unchanged
  v_uv = a_uv;
  v_field = a_field;  // interpolated as a position on the scale, looked up per fragment
  gl_Position = u_view_proj * vec4(v_world, 1.0);           // world -> clip
  gl_ClipDistance[0] = dot(vec4(v_world, 1.0), u_clip_plane);
}
)";

const std::string kClothFragment = std::string(kVersion) + kLighting + R"(
uniform vec3 u_front_color;
uniform vec3 u_back_color;
uniform vec2 u_cells;  // checker squares across u and v
in float v_field;
uniform bool u_field;          // colour by the field (both faces) instead of the checker
uniform sampler1D u_colormap;  // render/colormap.h colormap() at 256 positions, display values

// The checker box-filtered over the pixel's footprint (the integral of the square wave,
// after Inigo Quilez's "filterable procedurals"): crisp up close, its mean colour far away,
// never shimmering as the cloth moves.
float checker(vec2 p) {
  vec2 w = max(fwidth(p), vec2(1e-4));
  vec2 i = 2.0 * (abs(fract((p - 0.5 * w) * 0.5) - 0.5) - abs(fract((p + 0.5 * w) * 0.5) - 0.5)) / w;
  return 0.5 - 0.5 * i.x * i.y;
}

void main() {
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;                                  // two-sided: face the viewer
  vec3 albedo;
  if (u_field) {  // texel i holds colormap(i / 255): linear filtering interpolates between them
    albedo = to_linear(texture(u_colormap, (clamp(v_field, 0.0, 1.0) * 255.0 + 0.5) / 256.0).rgb);
  } else {
    vec3 base = gl_FrontFacing ? u_front_color : u_back_color;  // front and back differ
    albedo = to_linear(mix(base, base * 0.45 + vec3(0.5), checker(v_uv * u_cells)));  // dark/light squares
  }
  frag_color = to_display(shade(albedo, n, 24.0, 0.10));
}
)";

const std::string kSphereFragment = std::string(kVersion) + kLighting + R"(
uniform vec3 u_color;
void main() {
  frag_color = to_display(shade(to_linear(u_color), normalize(v_normal), 60.0, 0.40));
}
)";

const std::string kGroundFragment = std::string(kVersion) + R"(
in vec3 v_world;
out vec4 frag_color;
uniform vec3 u_eye;
uniform vec3 u_lit_color;  // display space: the ground's albedo under ambient + key light (a flat
                           // plane under a directional light is evenly lit: computed once, on the CPU)
uniform vec3 u_horizon;    // display space: the sky at the horizon, where the fog ends
uniform vec2 u_fog;        // fog start and end distance from the eye, m
uniform float u_spacing;   // m between minor grid lines

// 1 on a grid line about one pixel wide, 0 between lines; faded out where cells shrink
// to a few pixels, so the far ground does not turn into moire. w = fwidth(p).
float grid_line(vec2 p, vec2 w) {
  vec2 d = abs(fract(p - 0.5) - 0.5) / w;        // distance to the nearest line, in pixels
  float line = 1.0 - min(min(d.x, d.y), 1.0);
  return line * (1.0 - smoothstep(0.15, 0.4, max(w.x, w.y)));
}

void main() {
  vec2 p = v_world.xz / u_spacing;
  vec2 w = max(fwidth(p), vec2(1e-5));
  float lines = max(0.4 * grid_line(p, w), grid_line(p / 5.0, w / 5.0));  // a major line every 5 cells
  vec3 color = u_lit_color * (1.0 - 0.2 * lines);
  float fog = smoothstep(u_fog.x, u_fog.y, distance(v_world, u_eye));    // melts into the horizon
  frag_color = vec4(mix(color, u_horizon, fog), 1.0);
}
)";

const std::string kShadowVertex = std::string(kVersion) + R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform vec4 u_placement;      // as kSurfaceVertex
uniform vec3 u_light_dir;      // unit, towards the light; y > 0
uniform float u_ground_height;
void main() {
  vec3 p = u_placement.xyz + u_placement.w * a_position;                        // model -> world
  p -= u_light_dir * (max(p.y - u_ground_height, 0.0) / u_light_dir.y);          // down the light ray
  p.y = u_ground_height;                                                         // onto the plane
  gl_Position = u_view_proj * vec4(p, 1.0);
}
)";

const std::string kShadowFragment = std::string(kVersion) + R"(
out vec4 frag_color;
uniform float u_alpha;  // share of the lit ground's colour the shadow takes away
void main() { frag_color = vec4(0.0, 0.0, 0.0, u_alpha); }  // premultiplied: composited "over"
)";

const std::string kBackgroundVertex = std::string(kVersion) + R"(
out vec2 v_ndc;
void main() {
  const vec2 corners[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
  v_ndc = corners[gl_VertexID];               // one triangle covering the screen
  gl_Position = vec4(v_ndc, 1.0, 1.0);         // on the far plane: only where nothing was drawn
}
)";

const std::string kBackgroundFragment = std::string(kVersion) + R"(
in vec2 v_ndc;
out vec4 frag_color;
uniform vec3 u_right, u_up, u_forward;  // camera basis, world
uniform vec2 u_tan_half_fov;            // tan of half the horizontal and vertical fov
uniform vec3 u_horizon, u_zenith, u_nadir;  // display space
void main() {
  vec3 ray = normalize(u_forward + v_ndc.x * u_tan_half_fov.x * u_right
                                 + v_ndc.y * u_tan_half_fov.y * u_up);   // view ray of this pixel
  vec3 far_color = ray.y >= 0.0 ? u_zenith : u_nadir;                    // up: sky; down: backdrop
  float t = min(abs(ray.y) * 1.6, 1.0);
  frag_color = vec4(mix(u_horizon, far_color, t * (2.0 - t)), 1.0);       // eases out of the horizon
}
)";

const std::string kFlatVertex = std::string(kVersion) + R"(
layout(location = 0) in vec3 a_position;
uniform mat4 u_view_proj;
uniform float u_point_size;  // pixels
uniform vec4 u_clip_plane;   // as kSurfaceVertex
void main() {
  gl_Position = u_view_proj * vec4(a_position, 1.0);
  gl_ClipDistance[0] = dot(vec4(a_position, 1.0), u_clip_plane);
  gl_Position.z -= 2e-4 * gl_Position.w;  // drawn over the cloth they lie on
  gl_PointSize = u_point_size;
}
)";

const std::string kFlatFragment = std::string(kVersion) + R"(
out vec4 frag_color;
uniform vec3 u_color;  // display space
uniform bool u_ball;   // points: the square sprite shaded as a small lit ball
void main() {
  if (!u_ball) { frag_color = vec4(u_color, 1.0); return; }
  vec2 q = gl_PointCoord * 2.0 - 1.0;                        // -1..1 across the sprite
  float r2 = dot(q, q);
  float edge = clamp((1.0 - sqrt(r2)) * 6.0, 0.0, 1.0);       // alpha-to-coverage: a smooth rim
  vec3 n = vec3(q.x, -q.y, sqrt(max(1.0 - r2, 0.0)));         // sphere normal facing the viewer
  float diffuse = max(dot(n, vec3(-0.45, 0.6, 0.66)), 0.0);   // lit from the upper left, as the key light
  float highlight = pow(max(n.z * 0.8 + diffuse * 0.2, 0.0), 24.0) * 0.35;
  frag_color = vec4(u_color * (0.45 + 0.75 * diffuse) + vec3(highlight), edge);
}
)";

}  // namespace clothsim::shaders
