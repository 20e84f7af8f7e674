#include "gl_context.h"

#include <cstdlib>

#include "render/renderer.h"

namespace clothsim {

std::optional<GlBackend> parse_gl_backend(const std::string& text) {
  if (text == "auto") return GlBackend::automatic;
  if (text == "egl") return GlBackend::egl;
  if (text == "osmesa") return GlBackend::osmesa;
  return std::nullopt;
}

const char* gl_backend_name(GlBackend backend) {
  switch (backend) {
    case GlBackend::automatic: return "auto";
    case GlBackend::egl: return "egl";
    case GlBackend::osmesa: return "osmesa";
  }
  return "?";
}

std::vector<GlBackend> built_gl_backends() {
  std::vector<GlBackend> built;
#ifdef CLOTHSIM_HAVE_EGL
  built.push_back(GlBackend::egl);
#endif
#ifdef CLOTHSIM_HAVE_OSMESA
  built.push_back(GlBackend::osmesa);
#endif
  return built;
}

GlBackend gl_backend_from_environment() {
  const char* value = std::getenv("CLOTHSIM_GL");
  if (!value || !*value) return GlBackend::automatic;
  if (const auto backend = parse_gl_backend(value)) return *backend;
  throw RenderError(std::string("CLOTHSIM_GL=") + value + ": expected auto, egl or osmesa");
}

namespace {

std::unique_ptr<GlContext> create_one(GlBackend backend) {
  switch (backend) {
    case GlBackend::egl:
#ifdef CLOTHSIM_HAVE_EGL
      return create_egl_context();
#else
      throw RenderError("this clothsim was built without EGL (CMake found no libEGL)");
#endif
    case GlBackend::osmesa:
#ifdef CLOTHSIM_HAVE_OSMESA
      return create_osmesa_context();
#else
      throw RenderError("this clothsim was built without OSMesa (CMake found no libOSMesa)");
#endif
    case GlBackend::automatic: break;
  }
  throw RenderError("no GL backend chosen");
}

}  // namespace

std::unique_ptr<GlContext> create_gl_context(GlBackend backend) {
  if (backend != GlBackend::automatic) return create_one(backend);
  // auto: each built backend in turn (EGL first); if none gives a context, say what each said.
  std::string reasons;
  for (GlBackend b : built_gl_backends()) {
    try {
      return create_one(b);
    } catch (const RenderError& e) {
      reasons += std::string(reasons.empty() ? "" : "; ") + gl_backend_name(b) + ": " + e.what();
    }
  }
  throw RenderError("no OpenGL 3.3 core context (" + reasons + ")");
}

}  // namespace clothsim
