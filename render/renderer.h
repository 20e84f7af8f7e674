// The offscreen renderer: an OSMesa OpenGL 3.3 core context (llvmpipe: no GPU, no display),
// drawing a RenderFrame into a multisampled FBO and reading it back as an Image.
// It reads the snapshot and nothing of the engine.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "image.h"
#include "render_frame.h"

namespace clothsim {

struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Renderer {
 public:
  // Creates the context (throws RenderError naming what failed: context, GL version, shaders).
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders one frame, overlay text included. Throws RenderError on a bad size
  // (0, or above GL_MAX_RENDERBUFFER_SIZE) or a GL failure.
  Image render(const RenderFrame& frame);

  std::string gl_version() const;   // e.g. "4.5 (Core Profile) Mesa 22.3.6"
  std::string gl_renderer() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  int max_size() const;             // largest width/height accepted

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothsim
