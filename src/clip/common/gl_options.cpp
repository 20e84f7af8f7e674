#include "gl_options.h"

#include <cstdio>

#include "clip/common/cli_common.h"

namespace clothsim::clip {

GlBackend chosen_gl_backend(const GlOptions& options) {
  if (!options.gl.empty()) return *parse_gl_backend(options.gl);  // CLI11 checked the name
  try {
    return gl_backend_from_environment();
  } catch (const RenderError& e) {
    throw UsageError(e.what());
  }
}

std::unique_ptr<Renderer> make_renderer(const GlOptions& options) {
  auto renderer = std::make_unique<Renderer>(chosen_gl_backend(options));
  if (options.verbose)
    std::fprintf(stderr, "clothsim: GL: %s, %s, %s, %s\n", renderer->gl_backend().c_str(),
                 renderer->gl_vendor().c_str(), renderer->gl_renderer().c_str(), renderer->gl_version().c_str());
  return renderer;
}

PngText with_renderer(PngText text, const Renderer& renderer) {
  text.insert(text.end(), {{"gl_backend", renderer.gl_backend()},
                           {"gl_vendor", renderer.gl_vendor()},
                           {"gl_renderer", renderer.gl_renderer()},
                           {"gl_version", renderer.gl_version()}});
  return text;
}

}  // namespace clothsim::clip
