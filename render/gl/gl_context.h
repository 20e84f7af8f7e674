// Where the renderer's OpenGL 3.3 core context comes from: EGL or OSMesa, chosen at run time
// among the backends this build has (CMake builds whichever it finds).
//   egl     the surfaceless platform on Mesa (llvmpipe without a GPU, EGL_MESA_platform_surfaceless),
//           the device platform on NVIDIA's driver (EGL_EXT_platform_device, a GPU device first)
//   osmesa  Mesa's off-screen library (llvmpipe); Mesa removed it in 25.1
//   auto    EGL, then OSMesa if EGL gives no context
// MuJoCo's convention: the environment variable CLOTHSIM_GL=auto|egl|osmesa picks one, and
// the command line's --gl overrides it.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace clothsim {

enum class GlBackend { automatic, egl, osmesa };

std::optional<GlBackend> parse_gl_backend(const std::string& text);  // "auto", "egl", "osmesa"
const char* gl_backend_name(GlBackend backend);
std::vector<GlBackend> built_gl_backends();  // egl and/or osmesa, as CMake found them
// CLOTHSIM_GL, or automatic when unset; throws RenderError on another value.
GlBackend gl_backend_from_environment();

// One OpenGL 3.3 core context, with no window: the renderer draws into its own FBOs.
class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual void make_current() = 0;                    // on the calling thread; throws RenderError
  virtual void release() noexcept = 0;               // none current on the calling thread
  virtual void* proc_address(const char* name) = 0;  // a GL entry point of this context's library
  virtual std::string description() const = 0;       // e.g. "egl (surfaceless)", "osmesa"
};

// Throws RenderError with one line saying what each tried backend answered, or, before any
// backend is tried, naming an address-space limit (ulimit -v) the context cannot fit in:
// under one, Mesa's context creation and shader build crash instead of failing.
std::unique_ptr<GlContext> create_gl_context(GlBackend backend);

// "" when `bytes` more fit under RLIMIT_AS (ulimit -v) beside what the process maps now,
// else why not, on one line naming the limit and the least that would do.
std::string address_space_shortfall(double bytes, const std::string& what);
// Address space an OpenGL context and a still take beyond what the process maps when the
// context is made (llvmpipe: its rasterizer threads' stacks and malloc arenas, LLVM, the
// shaders); BENCHMARKS.md, "Memory estimate", has the measurements.
double gl_context_address_space();
// Throws RenderError when a framebuffer of that size would not fit (address_space_shortfall):
// colour and depth per sample, the resolved copy and the readback (memory_budget.h's
// render_bytes counts the same).
void require_framebuffer_space(int width, int height, int samples);

// Per backend (defined only when built; create_gl_context chooses).
std::unique_ptr<GlContext> create_egl_context();
std::unique_ptr<GlContext> create_osmesa_context();

}  // namespace clothsim
