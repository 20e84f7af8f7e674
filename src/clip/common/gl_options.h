// The renderer as the commands that draw make it: --gl auto|egl|osmesa over the environment's
// CLOTHSIM_GL (MuJoCo's MUJOCO_GL convention), --verbose saying which GL it got, and the
// same in every PNG's metadata, so an image says what drew it.
#pragma once

#include <memory>
#include <string>

#include "render/png_io.h"
#include "render/renderer.h"

namespace clothsim::clip {

struct GlOptions {
  std::string gl;        // --gl; empty: CLOTHSIM_GL, else auto
  bool verbose = false;  // --verbose
};

// --gl, else CLOTHSIM_GL, else auto. A bad CLOTHSIM_GL is a UsageError (exit 2).
GlBackend chosen_gl_backend(const GlOptions& options);

// Creates the renderer (RenderError if no backend gives a context); with --verbose prints
// "clothsim: GL: egl (surfaceless), Mesa/X.org, llvmpipe (...), 4.5 (Core Profile) Mesa ..."
// on stderr.
std::unique_ptr<Renderer> make_renderer(const GlOptions& options);

// `text` followed by the tEXt chunks gl_backend, gl_vendor, gl_renderer, gl_version.
PngText with_renderer(PngText text, const Renderer& renderer);

}  // namespace clothsim::clip
