// The frame, pass by pass (each a function below):
//   backdrop      the grid ground (evenly lit, fogged into the horizon) and the sky depend on
//                 the camera and size only: rendered once, resolved, read back and kept
//   region        the screen rectangle the cloth, spheres and shadows can cover (frame_setup.h);
//                 the passes below are scissored to it, the rest of the image is backdrop
//   lit surfaces  into a multisampled FBO cleared to transparent black: cloth (two-sided,
//                 checker, or a field through the colormap texture) and spheres, Blinn-Phong;
//                 springs and particles; with a ground, clipped at its plane (it is opaque)
//   shadows       cloth and spheres flattened onto the ground along the light (Blinn 1988),
//                 written as translucent black just above the plane, each pixel once
//   resolve       MSAA samples averaged into a single-sample FBO (glBlitFramebuffer): colour
//                 premultiplied by coverage, alpha = coverage
//   read back     glFinish, glReadPixels, rows flipped to top-down, composited over the
//                 backdrop (out = colour + (1 - alpha) backdrop), so alpha ends at 255
//   fxaa          (RenderFrame::fxaa) the edges of what was drawn smoothed on the CPU, in place
//                 of MSAA (render/fxaa.h); the backdrop is drawn with 4 samples all the same
//   overlay       text, colour bar and series inset drawn on the CPU (frame_setup.h)
// Why the backdrop, the region and FXAA: llvmpipe shades on the CPU, with per-sample work under
// MSAA, so pixels and samples are the cost. Drawing ground and sky every frame cost as much as
// all the rest; clearing and resolving the whole multisampled image, a third of what remained;
// 4x MSAA on a compare tile, nearly half of the tile (BENCHMARKS.md, "Renderer and PNG").
//
// GL objects (programs, buffers, FBOs, the backdrop) live as long as the Renderer; the FBOs
// are re-made only when the size or sample count changes. Several Renderers may exist in one
// process, on one thread or on several, through one backend or both (EGL, OSMesa: gl_context.h):
// each owns its context and its table of GL entry points (gl_functions.h), and render() makes
// both current on the calling thread first (contexts are current per thread). One Renderer
// must not be used by two threads at once.
#include "renderer.h"

#include "render/gl/gl_program.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "colormap.h"
#include "frame_setup.h"
#include "fxaa.h"
#include "render/gl/gl_context.h"
#include "render/gl/gl_math.h"
#include "render/gl/gl_uniforms.h"
#include "render/gl/meshes.h"
#include "render/gl/shaders.h"

namespace clothsim {

using namespace render;  // frame_setup.h: View, lights, colour conventions

namespace {

using gl::attribute, gl::set, gl::set_placement, gl::upload;  // render/gl/gl_uniforms.h

// Camera and lights for the lit programs (kLighting in shaders.cpp).
void set_lights(GLuint program, const View& view) {
  set(program, "u_view_proj", view.view_proj);
  set(program, "u_eye", view.eye);
  set(program, "u_light_dir", view.light_dir);
  set(program, "u_key", kKeyLight);
  set(program, "u_sky", kSkyLight);
  set(program, "u_bounce", kBounceLight);
}

// Points above the ground plane y = h have a positive distance (gl_ClipDistance[0]).
void set_ground_clip(GLuint program, const RenderFrame& frame) {
  glUniform4f(glGetUniformLocation(program, "u_clip_plane"), 0.f, 1.f, 0.f, -frame.ground_height);
}

}  // namespace

struct Renderer::Impl {
  std::unique_ptr<GlContext> context;                           // EGL or OSMesa (gl_context.h)
  gl::Functions functions;                                      // its entry points (gl_functions.h)
  std::string version, vendor, renderer_name;
  int max_size = 0, max_samples = 1;
  float max_line_width = 1.f;                                   // GL_ALIASED_LINE_WIDTH_RANGE[1]

  GLuint cloth_program = 0, sphere_program = 0, ground_program = 0, shadow_program = 0;
  GLuint background_program = 0, flat_program = 0;

  GLuint empty_vao = 0;                                         // attribute-less full-screen draw
  GLuint cloth_vao = 0, cloth_positions = 0, cloth_normals = 0, cloth_uv = 0, cloth_triangles = 0;
  GLuint cloth_field = 0;                                       // (P) scale positions 0..1; zeros without a field
  GLuint colormap_texture = 0;                                  // 1-D, colormap() at 256 positions
  std::vector<float> field_positions;                           // scratch for cloth_field
  GLuint lines_vao = 0, line_indices = 0;                       // springs: cloth_positions + indices
  struct SphereMesh {                                           // a unit sphere on the GPU
    GLuint vao = 0, positions = 0, normals = 0, triangles = 0;
    GLsizei index_count = 0;
  };
  std::map<int, SphereMesh> sphere_meshes;                      // by slices (sphere_slices), made when first asked for
  GLuint ground_vao = 0, ground_positions = 0;

  GLuint draw_fbo = 0, draw_color = 0, draw_depth = 0;          // multisampled when samples > 1
  GLuint resolve_fbo = 0, resolve_color = 0;
  int target_width = 0, target_height = 0, target_samples = 0;

  std::vector<std::uint8_t> readback;                           // the region's rows, bottom-up, as GL returns them
  std::vector<std::uint8_t> drawn;                              // FXAA's mask: the region's coverage, top-down
  Image backdrop;                                               // ground + sky, top-down, opaque
  std::vector<float> backdrop_key;                              // what it was rendered for
  std::array<GLint, 4> line_ranges{};                           // first index of each spring type, and the end

  void make_current() {
    context->make_current();
    gl::current = &functions;                                   // the GL names now call this context
  }
  // EGL lets a context be current on one thread at a time and refuses it elsewhere until
  // released (OSMesa does not care): released after each use, a Renderer can move between
  // threads (compare renders on a worker) and backends can alternate on one thread.
  void release() noexcept {
    context->release();
    if (gl::current == &functions) gl::current = nullptr;
  }
  struct Current {  // current for a scope
    Impl& r;
    explicit Current(Impl& impl) : r(impl) { r.make_current(); }
    ~Current() { r.release(); }
  };
  void create_objects();
  const SphereMesh& sphere_mesh(int slices);
  void ensure_targets(int width, int height, int samples);
  void delete_targets();
  void upload_frame(const RenderFrame& frame, const View& view);
  void draw_lit_surfaces(const RenderFrame& frame, const View& view);
  void draw_springs_and_particles(const RenderFrame& frame, const View& view);
  void draw_shadows(const RenderFrame& frame, const View& view);
  void draw_ground(const RenderFrame& frame, const View& view);
  void draw_sky(const RenderFrame& frame, const View& view);
  void ensure_backdrop(const RenderFrame& frame, const View& view);
  void resolve_and_read(const PixelRect& region);
  Image composite_over_backdrop(const PixelRect& region) const;
  void smooth_edges(Image& image, const PixelRect& region);
};

Renderer::Renderer(GlBackend backend) : impl_(std::make_unique<Impl>()) {
  Impl& r = *impl_;
  r.context = create_gl_context(backend);  // OpenGL 3.3 core asked for (llvmpipe gives 4.5)
  if (const char* missing = gl::load_functions(
          r.functions, [](const char* name, void* c) { return static_cast<GlContext*>(c)->proc_address(name); },
          r.context.get()))
    throw RenderError(r.context->description() + " has no " + missing);
  const Impl::Current current(r);  // released also when a check below throws
  const auto text = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  r.version = text(GL_VERSION);
  r.vendor = text(GL_VENDOR);
  r.renderer_name = text(GL_RENDERER);
  GLint major = 0, minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33)
    throw RenderError("OpenGL 3.3 is needed, the " + r.context->description() + " context offers \"" + r.version +
                      "\" on " + r.renderer_name);
  GLint renderbuffer_max = 0, viewport_max[2] = {0, 0}, samples = 1;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer_max);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport_max);
  glGetIntegerv(GL_MAX_SAMPLES, &samples);
  r.max_size = std::min({renderbuffer_max, viewport_max[0], viewport_max[1]});
  r.max_samples = std::max(1, samples);
  GLfloat line_widths[2] = {1.f, 1.f};
  glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, line_widths);
  r.max_line_width = std::max(1.f, line_widths[1]);
  r.create_objects();
}

// The context frees every GL object it owns when destroyed.
Renderer::~Renderer() {
  if (impl_ && gl::current == &impl_->functions) gl::current = nullptr;
}

void Renderer::make_current() { impl_->make_current(); }

std::string Renderer::gl_version() const { return impl_->version; }
std::string Renderer::gl_renderer() const { return impl_->renderer_name; }
std::string Renderer::gl_vendor() const { return impl_->vendor; }
std::string Renderer::gl_backend() const { return impl_->context->description(); }
int Renderer::max_size() const { return impl_->max_size; }

void Renderer::Impl::create_objects() {
  cloth_program = gl::build_program("cloth", shaders::kSurfaceVertex, shaders::kClothFragment);
  sphere_program = gl::build_program("sphere", shaders::kSurfaceVertex, shaders::kSphereFragment);
  ground_program = gl::build_program("ground", shaders::kSurfaceVertex, shaders::kGroundFragment);
  shadow_program = gl::build_program("shadow", shaders::kShadowVertex, shaders::kShadowFragment);
  background_program = gl::build_program("background", shaders::kBackgroundVertex, shaders::kBackgroundFragment);
  flat_program = gl::build_program("line/point", shaders::kFlatVertex, shaders::kFlatFragment);

  glGenVertexArrays(1, &empty_vao);

  GLuint buffers[7];
  glGenBuffers(7, buffers);
  cloth_positions = buffers[0]; cloth_normals = buffers[1]; cloth_uv = buffers[2];
  cloth_triangles = buffers[3]; line_indices = buffers[4];
  ground_positions = buffers[5]; cloth_field = buffers[6];

  glGenVertexArrays(1, &cloth_vao);
  glBindVertexArray(cloth_vao);
  attribute(0, cloth_positions, 3);
  attribute(1, cloth_normals, 3);
  attribute(2, cloth_uv, 2);
  attribute(3, cloth_field, 1);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, cloth_triangles);

  // The colormap as a texture sampled from its one definition (colormap.h): texel i holds
  // colormap(i / 255), so the cloth and the colour bar drawn on the CPU show the same colours.
  std::vector<std::uint8_t> texels;
  for (int i = 0; i < 256; ++i) {
    const auto c = render::colormap_rgb8(static_cast<float>(i) / 255.f);
    texels.insert(texels.end(), c.begin(), c.end());
  }
  glGenTextures(1, &colormap_texture);
  glBindTexture(GL_TEXTURE_1D, colormap_texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage1D(GL_TEXTURE_1D, 0, GL_RGB8, 256, 0, GL_RGB, GL_UNSIGNED_BYTE, texels.data());
  glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_1D, 0);

  glGenVertexArrays(1, &lines_vao);
  glBindVertexArray(lines_vao);
  attribute(0, cloth_positions, 3);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, line_indices);

  glGenVertexArrays(1, &ground_vao);
  glBindVertexArray(ground_vao);
  attribute(0, ground_positions, 3);
  glBindVertexArray(0);
  gl::check_gl("creating programs and buffers");
}

void Renderer::Impl::delete_targets() {
  const GLuint fbos[2] = {draw_fbo, resolve_fbo};
  const GLuint renderbuffers[3] = {draw_color, draw_depth, resolve_color};
  glDeleteFramebuffers(2, fbos);
  glDeleteRenderbuffers(3, renderbuffers);
  draw_fbo = resolve_fbo = draw_color = draw_depth = resolve_color = 0;
  target_width = target_height = target_samples = 0;
}

// Each level of detail is built once, at its first use, and kept: a run asks for a few.
const Renderer::Impl::SphereMesh& Renderer::Impl::sphere_mesh(int slices) {
  auto [it, made] = sphere_meshes.try_emplace(slices);
  SphereMesh& m = it->second;
  if (!made) return m;
  const Mesh sphere = make_unit_sphere(slices, slices / 2);
  GLuint buffers[3];
  glGenBuffers(3, buffers);
  m.positions = buffers[0], m.normals = buffers[1], m.triangles = buffers[2];
  glGenVertexArrays(1, &m.vao);
  glBindVertexArray(m.vao);
  upload(GL_ARRAY_BUFFER, m.positions, sphere.positions);
  upload(GL_ARRAY_BUFFER, m.normals, sphere.normals);
  attribute(0, m.positions, 3);
  attribute(1, m.normals, 3);
  upload(GL_ELEMENT_ARRAY_BUFFER, m.triangles, sphere.triangles);
  m.index_count = static_cast<GLsizei>(sphere.triangles.size());
  return m;
}

void Renderer::Impl::ensure_targets(int width, int height, int samples) {
  if (width == target_width && height == target_height && samples == target_samples) return;
  require_framebuffer_space(width, height, samples);  // under ulimit -v llvmpipe may crash instead
  delete_targets();
  const auto make_renderbuffer = [&](GLenum format, int n) {
    GLuint rb = 0;
    glGenRenderbuffers(1, &rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (n > 1) glRenderbufferStorageMultisample(GL_RENDERBUFFER, n, format, width, height);
    else glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    return rb;
  };
  draw_color = make_renderbuffer(GL_RGBA8, samples);
  draw_depth = make_renderbuffer(GL_DEPTH_COMPONENT24, samples);
  glGenFramebuffers(1, &draw_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, draw_color);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, draw_depth);
  const GLenum draw_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  GLenum resolve_status = GL_FRAMEBUFFER_COMPLETE;
  if (samples > 1) {  // the single-sample copy that glReadPixels reads
    resolve_color = make_renderbuffer(GL_RGBA8, 1);
    glGenFramebuffers(1, &resolve_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_color);
    resolve_status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR || draw_status != GL_FRAMEBUFFER_COMPLETE || resolve_status != GL_FRAMEBUFFER_COMPLETE) {
    delete_targets();
    throw RenderError("cannot make a " + std::to_string(width) + "x" + std::to_string(height) +
                      " framebuffer with " + std::to_string(samples) + " samples" +
                      (error == GL_OUT_OF_MEMORY ? ": out of memory" : ""));
  }
  target_width = width;
  target_height = height;
  target_samples = samples;
  readback.resize(static_cast<std::size_t>(width) * height * 4);
}

void Renderer::Impl::upload_frame(const RenderFrame& frame, const View& view) {
  upload(GL_ARRAY_BUFFER, cloth_positions, frame.cloth_positions);
  upload(GL_ARRAY_BUFFER, cloth_normals, frame.cloth_normals);
  upload(GL_ARRAY_BUFFER, cloth_uv, frame.cloth_uv);
  // Always P values, so attribute 3 never reads past its buffer; the shader ignores zeros
  // unless u_field is set.
  field_positions.assign(frame.cloth_positions.size() / 3, 0.f);
  for (std::size_t i = 0; i < frame.cloth_field.size() && i < field_positions.size(); ++i)
    field_positions[i] = render::scale_position(frame.color_scale, frame.cloth_field[i]);
  upload(GL_ARRAY_BUFFER, cloth_field, field_positions);
  glBindVertexArray(cloth_vao);
  upload(GL_ELEMENT_ARRAY_BUFFER, cloth_triangles, frame.cloth_triangles);

  if (!frame.spring_lines.empty()) {  // grouped by type so each type is one draw in its colour
    std::vector<std::uint32_t> sorted;
    sorted.reserve(frame.spring_lines.size());
    for (std::uint8_t type = 0; type < 3; ++type) {
      line_ranges[type] = static_cast<GLint>(sorted.size());
      for (std::size_t l = 0; l < frame.spring_types.size(); ++l)
        if (std::min<std::uint8_t>(frame.spring_types[l], 2) == type)
          sorted.insert(sorted.end(), {frame.spring_lines[2 * l], frame.spring_lines[2 * l + 1]});
    }
    line_ranges[3] = static_cast<GLint>(sorted.size());
    glBindVertexArray(lines_vao);
    upload(GL_ELEMENT_ARRAY_BUFFER, line_indices, sorted);
  }

  if (frame.has_ground) {  // a square around the camera target, reaching past where the fog hides it
    const float y = frame.ground_height, half = 8.f * view.distance;
    const float cx = frame.camera.target[0], cz = frame.camera.target[2];
    const std::vector<float> quad = {cx - half, y, cz - half, cx - half, y, cz + half,
                                     cx + half, y, cz - half, cx + half, y, cz + half};
    upload(GL_ARRAY_BUFFER, ground_positions, quad);
  }
  glBindVertexArray(0);
}


void Renderer::Impl::draw_lit_surfaces(const RenderFrame& frame, const View& view) {
  if (!frame.cloth_triangles.empty()) {
    glUseProgram(cloth_program);
    set_lights(cloth_program, view);
    set_ground_clip(cloth_program, frame);
    set_placement(cloth_program, {0.f, 0.f, 0.f}, 1.f);
    set(cloth_program, "u_front_color", frame.cloth_front);
    set(cloth_program, "u_back_color", frame.cloth_back);
    set(cloth_program, "u_cells", static_cast<float>(frame.checker_cells_u), static_cast<float>(frame.checker_cells_v));
    set(cloth_program, "u_field", frame.cloth_field.empty() ? 0 : 1);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_1D, colormap_texture);
    set(cloth_program, "u_colormap", 0);
    glBindVertexArray(cloth_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(frame.cloth_triangles.size()), GL_UNSIGNED_INT, nullptr);  // both faces
  }
  if (!frame.spheres.empty()) {
    glUseProgram(sphere_program);
    set_lights(sphere_program, view);
    set_ground_clip(sphere_program, frame);
    glEnable(GL_CULL_FACE);                                         // closed mesh: back faces never show
    for (const RenderSphere& s : frame.spheres) {
      const SphereMesh& mesh = sphere_mesh(sphere_slices(sphere_radius_px(gl::to_vec3(s.center), s.radius, view, frame.height)));
      glBindVertexArray(mesh.vao);
      set_placement(sphere_program, gl::to_vec3(s.center), s.radius);
      set(sphere_program, "u_color", s.color);
      glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
    }
    glDisable(GL_CULL_FACE);
  }
}

void Renderer::Impl::draw_springs_and_particles(const RenderFrame& frame, const View& view) {
  // Without a surface (a chain, a single spring) the lines and particles are the whole picture:
  // drawn larger, as the course's UI drew them over the cloth.
  const bool alone = frame.cloth_triangles.empty();
  const float scale = std::max(1.f, static_cast<float>(frame.height) / 360.f);
  glUseProgram(flat_program);
  set(flat_program, "u_view_proj", view.view_proj);
  set_ground_clip(flat_program, frame);
  if (!frame.spring_lines.empty()) {
    set(flat_program, "u_ball", 0);
    glLineWidth(std::min(alone ? 2.f * scale : 1.f, max_line_width));
    const Vec3 colors[3] = {{0.12f, 0.12f, 0.14f}, {0.10f, 0.55f, 0.25f}, {0.80f, 0.20f, 0.60f}};  // structural, shear, bend
    glBindVertexArray(lines_vao);
    for (int type = 2; type >= 0; --type) {  // structural last: on top where lines coincide
      set(flat_program, "u_color", colors[type]);
      glDrawElements(GL_LINES, line_ranges[type + 1] - line_ranges[type], GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(static_cast<std::uintptr_t>(line_ranges[type]) * sizeof(std::uint32_t)));
    }
    glLineWidth(1.f);
  }
  if (frame.draw_particles && !frame.cloth_positions.empty()) {
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);  // the sprite's soft rim becomes sample coverage ...
    glEnable(GL_SAMPLE_ALPHA_TO_ONE);       // ... and what is written stays opaque
    set(flat_program, "u_ball", 1);
    set(flat_program, "u_point_size", (alone ? 7.f : 3.f) * scale);
    set(flat_program, "u_color", alone ? Vec3{0.20f, 0.32f, 0.55f} : Vec3{0.10f, 0.10f, 0.12f});
    glBindVertexArray(cloth_vao);
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(frame.cloth_positions.size() / 3));
    glDisable(GL_SAMPLE_ALPHA_TO_ONE);
    glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    glDisable(GL_PROGRAM_POINT_SIZE);
  }
}

void Renderer::Impl::draw_shadows(const RenderFrame& frame, const View& view) {
  // Where the key light is blocked, the ground keeps its sky light plus a fifth of the key light
  // (standing in for what the surroundings scatter: a black shadow reads as a hole). As the
  // backdrop shows the lit ground, the shadow is the fraction of it to take away: its alpha.
  const Vec3 lit = kSkyLight + kKeyLight * view.light_dir.y, shaded = kSkyLight + kKeyLight * (0.2f * view.light_dir.y);
  const float kept = std::sqrt((shaded.x + shaded.y + shaded.z) / (lit.x + lit.y + lit.z));  // display space
  glUseProgram(shadow_program);
  set(shadow_program, "u_view_proj", view.view_proj);
  set(shadow_program, "u_light_dir", view.light_dir);
  set(shadow_program, "u_ground_height", frame.ground_height);
  set(shadow_program, "u_alpha", 1.f - kept);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(-1.f, -4.f);  // just above the plane; overlapping casters: equal depth fails GL_LESS
  set_placement(shadow_program, {0.f, 0.f, 0.f}, 1.f);
  glBindVertexArray(cloth_vao);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(frame.cloth_triangles.size()), GL_UNSIGNED_INT, nullptr);
  // A sphere's two halves project onto the same disc with opposite windings: one is enough.
  glEnable(GL_CULL_FACE);
  for (const RenderSphere& s : frame.spheres) {
    const SphereMesh& mesh = sphere_mesh(sphere_slices(
        sphere_shadow_radius_px(gl::to_vec3(s.center), s.radius, frame.ground_height, view, frame.height)));
    glBindVertexArray(mesh.vao);
    set_placement(shadow_program, gl::to_vec3(s.center), s.radius);
    glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
  }
  glDisable(GL_CULL_FACE);
  glDisable(GL_POLYGON_OFFSET_FILL);
}

void Renderer::Impl::draw_ground(const RenderFrame& frame, const View& view) {
  // A horizontal plane under a directional light is evenly lit: its colour is computed once.
  const Vec3 lit = mul(linear(frame.ground_color), kSkyLight + kKeyLight * view.light_dir.y);
  glUseProgram(ground_program);
  set(ground_program, "u_view_proj", view.view_proj);
  set_placement(ground_program, {0.f, 0.f, 0.f}, 1.f);
  set(ground_program, "u_eye", view.eye);
  set(ground_program, "u_lit_color", display(lit));
  set(ground_program, "u_horizon", to_vec3(frame.background));
  set(ground_program, "u_fog", 1.6f * view.distance, 5.f * view.distance);
  set(ground_program, "u_spacing", std::max(frame.ground_grid_spacing, 1e-3f));
  glBindVertexArray(ground_vao);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
}

void Renderer::Impl::draw_sky(const RenderFrame& frame, const View& view) {
  const Vec3 horizon = to_vec3(frame.background);  // display values throughout
  glUseProgram(background_program);
  set(background_program, "u_right", view.right);
  set(background_program, "u_up", view.up);
  set(background_program, "u_forward", view.forward);
  set(background_program, "u_tan_half_fov", view.tan_half_x, view.tan_half_y);
  set(background_program, "u_horizon", horizon);
  set(background_program, "u_zenith", mul(horizon, {0.70f, 0.80f, 0.94f}));   // deeper, cooler above
  // Without ground, a studio backdrop darkening below the horizon; with ground, the fogged
  // ground already meets the horizon colour.
  set(background_program, "u_nadir", frame.has_ground ? horizon : mul(horizon, {0.80f, 0.79f, 0.78f}));
  glDepthFunc(GL_LEQUAL);                                        // the far plane, where nothing was drawn
  glDepthMask(GL_FALSE);
  glBindVertexArray(empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

// Renders ground and sky into `backdrop` unless it already shows this camera, size and ground.
// Under FXAA it is drawn with 4 samples all the same (it is drawn once per camera, and the
// ground's thin grid lines are what FXAA cannot mend), so the targets may change samples here.
void Renderer::Impl::ensure_backdrop(const RenderFrame& frame, const View& view) {
  const RenderCamera& c = frame.camera;
  const int frame_samples = std::clamp(frame.samples, 1, max_samples);
  const int samples = frame.fxaa ? std::max(frame_samples, std::min(kDefaultMsaaSamples, max_samples)) : frame_samples;
  std::vector<float> key = {static_cast<float>(frame.width), static_cast<float>(frame.height),
                            static_cast<float>(samples), c.fov_deg, frame.has_ground ? 1.f : 0.f,
                            frame.ground_height, frame.ground_grid_spacing};
  for (const auto* a : {&c.eye, &c.target, &c.up}) key.insert(key.end(), a->begin(), a->end());
  for (const auto* a : {&frame.background, &frame.ground_color}) key.insert(key.end(), a->begin(), a->end());
  if (key == backdrop_key) return;
  ensure_targets(frame.width, frame.height, samples);
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo);
  glViewport(0, 0, frame.width, frame.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClear(GL_DEPTH_BUFFER_BIT);
  if (frame.has_ground) draw_ground(frame, view);
  draw_sky(frame, view);
  resolve_and_read(PixelRect{0, 0, frame.width, frame.height});
  backdrop = Image(frame.width, frame.height);
  const std::size_t row_bytes = static_cast<std::size_t>(frame.width) * 4;
  for (int y = 0; y < frame.height; ++y)                                      // GL rows are bottom-up
    std::memcpy(backdrop.pixel(0, y), readback.data() + static_cast<std::size_t>(frame.height - 1 - y) * row_bytes, row_bytes);
  backdrop_key = key;
}

// Resolves and reads `region` only; readback then holds its rows, bottom-up, tightly packed.
void Renderer::Impl::resolve_and_read(const PixelRect& region) {
  const int x0 = region.x0, y0 = region.y0, x1 = region.x1, y1 = region.y1;
  if (target_samples > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo);
    glBlitFramebuffer(x0, y0, x1, y1, x0, y0, x1, y1, GL_COLOR_BUFFER_BIT, GL_NEAREST);  // MSAA resolve
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo);
  } else {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo);
  }
  glFinish();                                                                  // all drawing done
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(x0, y0, region.width(), region.height(), GL_RGBA, GL_UNSIGNED_BYTE, readback.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::check_gl("drawing and reading back a " + std::to_string(target_width) + "x" +
               std::to_string(target_height) + " frame");
}

// Rows flipped to top-down, the premultiplied frame laid over the backdrop: "over" with
// integer arithmetic, so the bytes are the same on every machine; alpha ends at 255.
// Outside `region` nothing was drawn: the backdrop shows as it is.
Image Renderer::Impl::composite_over_backdrop(const PixelRect& region) const {
  Image image = backdrop;
  const int w = region.width();
  for (int gl_row = region.y0; gl_row < region.y1; ++gl_row) {
    const int y = target_height - 1 - gl_row;                                  // GL rows are bottom-up
    const std::uint8_t* src = readback.data() + static_cast<std::size_t>(gl_row - region.y0) * w * 4;
    const std::uint8_t* back = backdrop.pixel(region.x0, y);
    std::uint8_t* dst = image.pixel(region.x0, y);
    for (int i = 0; i < 4 * w; i += 4) {
      const int uncovered = 255 - src[i + 3];
      if (uncovered == 255) continue;                         // most pixels: backdrop only
      if (uncovered == 0) {                                   // inside geometry
        std::memcpy(dst + i, src + i, 3);
      } else {                                                // edges and shadows
        for (int c = 0; c < 3; ++c)
          dst[i + c] = static_cast<std::uint8_t>(std::min(255, src[i + c] + (back[i + c] * uncovered + 127) / 255));
      }
    }
  }
  return image;
}

// FXAA over the region, on the pixels the frame drew (readback's alpha: coverage) and their
// neighbours: the backdrop elsewhere stays as it was drawn.
void Renderer::Impl::smooth_edges(Image& image, const PixelRect& region) {
  const int w = region.width(), h = region.height();
  drawn.resize(static_cast<std::size_t>(w) * h);
  for (int row = 0; row < h; ++row) {                                  // top-down over the region
    const std::uint8_t* src = readback.data() + static_cast<std::size_t>(h - 1 - row) * w * 4;
    std::uint8_t* dst = drawn.data() + static_cast<std::size_t>(row) * w;
    for (int i = 0; i < w; ++i) dst[i] = src[4 * i + 3];
  }
  const int top = target_height - region.y1;                           // GL rows are bottom-up
  fxaa(image, region.x0, top, region.x1, top + h, drawn.data());
}

Image Renderer::render(const RenderFrame& frame) {
  Impl& r = *impl_;
  validate_frame(frame, r.max_size);                                   // sizes and indices, before any GL
  const Impl::Current current(r);                                      // ours, on this thread, until we return
  const View view = make_view(frame);                                  // camera and key light
  r.upload_frame(frame, view);                                         // cloth, springs, ground quad
  r.ensure_backdrop(frame, view);                                      // ground + sky, once per camera
  r.ensure_targets(frame.width, frame.height, std::clamp(frame.samples, 1, r.max_samples));
  glBindFramebuffer(GL_FRAMEBUFFER, r.draw_fbo);
  glViewport(0, 0, frame.width, frame.height);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // Lines, particle sprites and anti-aliased edges reach a few pixels past the geometry.
  const PixelRect region = drawn_region(frame, view, 4 + 4 * std::max(1, frame.height / 360));
  Image image;
  if (region.empty()) {
    image = r.backdrop;                                                // nothing in view
  } else {
    glEnable(GL_SCISSOR_TEST);                                         // clear and draw only there
    glScissor(region.x0, region.y0, region.width(), region.height());
    glClearColor(0.f, 0.f, 0.f, 0.f);                                  // transparent: the backdrop shows
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (frame.has_ground) glEnable(GL_CLIP_DISTANCE0);                // nothing shows below the ground
    r.draw_lit_surfaces(frame, view);
    r.draw_springs_and_particles(frame, view);
    glDisable(GL_CLIP_DISTANCE0);
    if (frame.has_ground && frame.shadows) r.draw_shadows(frame, view);
    glDisable(GL_SCISSOR_TEST);
    r.resolve_and_read(region);                                        // resolve, finish, read
    image = r.composite_over_backdrop(region);                         // flip, over the backdrop
    if (frame.fxaa) r.smooth_edges(image, region);                     // FXAA on what was drawn
  }
  draw_overlay(image, frame);                                          // text on the CPU
  return image;
}

}  // namespace clothsim
