// The OSMesa backend: Mesa's off-screen library (llvmpipe), an OpenGL 3.3 core context
// drawing into a 1x1 client buffer it requires; the renderer draws into its own FBOs.
#include <GL/osmesa.h>

#include <array>
#include <cstdint>

#include "gl_context.h"
#include "render_error.h"

namespace clothsim {

namespace {

class OsmesaContext final : public GlContext {
 public:
  OsmesaContext() {
    // No depth/stencil on the window buffer, the FBOs have their own.
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                              OSMESA_ACCUM_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_)
      throw RenderError("cannot create an OSMesa OpenGL 3.3 core context (is Mesa's libOSMesa with llvmpipe installed?)");
  }
  ~OsmesaContext() override { OSMesaDestroyContext(context_); }  // frees every GL object it owns

  void make_current() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw RenderError("OSMesaMakeCurrent failed");
  }
  void release() noexcept override { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }
  void* proc_address(const char* name) override { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }
  std::string description() const override { return "osmesa"; }

 private:
  OSMesaContext context_ = nullptr;
  std::array<std::uint8_t, 4> buffer_{};
};

}  // namespace

std::unique_ptr<GlContext> create_osmesa_context() { return std::make_unique<OsmesaContext>(); }

}  // namespace clothsim
