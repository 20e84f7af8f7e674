// The offscreen renderer: an OpenGL 3.3 core context through EGL or OSMesa (gl_context.h;
// llvmpipe without a GPU, the GPU on NVIDIA's driver; no display either way),
// drawing a RenderFrame into a multisampled FBO and reading it back as an Image.
// It reads the snapshot and nothing of the engine.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "render/gl/gl_context.h"
#include "render/gl/render_error.h"  // RenderError, which every user of the renderer catches
#include "image.h"
#include "view/render_frame.h"

namespace clothsim {

class Renderer {
 public:
  // Creates the context through `backend` (default: CLOTHSIM_GL, else auto: EGL then OSMesa).
  // Throws RenderError naming what failed: context, GL version, shaders.
  explicit Renderer(GlBackend backend = gl_backend_from_environment());
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders one frame, overlay text included. Throws RenderError on a bad size
  // (0, or above GL_MAX_RENDERBUFFER_SIZE) or a GL failure.
  Image render(const RenderFrame& frame);

  // For code that calls GL itself (tests): makes this context current on the calling thread
  // until the next render() returns. render() makes it current and releases it on its own.
  void make_current();

  std::string gl_version() const;   // e.g. "4.5 (Core Profile) Mesa 22.3.6"
  std::string gl_renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string gl_vendor() const;    // e.g. "Mesa/X.org"
  std::string gl_backend() const;   // e.g. "egl (surfaceless)", "osmesa"
  int max_size() const;             // largest width/height accepted

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim
