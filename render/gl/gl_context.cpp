#include "gl_context.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "render_error.h"

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

namespace {
// Measured growth of VmPeak over the process at context creation, `run --still` on the drape
// (Mesa 22.3, llvmpipe): 255 MiB with LP_NUM_THREADS=0, 147 MiB more per rasterizer thread
// (its stack, and the 128 MiB glibc maps while aligning the thread's malloc arena).
constexpr double kMiB = 1024.0 * 1024;
constexpr double kContextBytes = 264 * kMiB, kPerRasterThread = 152 * kMiB;
constexpr int kMaxRasterThreads = 16;  // llvmpipe's LP_MAX_THREADS in Mesa 22

int raster_threads() {
  if (const char* n = std::getenv("LP_NUM_THREADS"); n && *n) return std::clamp(std::atoi(n), 0, kMaxRasterThreads);
  return std::clamp(static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN)), 1, kMaxRasterThreads);
}

double mapped_bytes() {  // VmSize: the first field of /proc/self/statm, in pages
  long pages = 0;
  if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld", &pages) != 1) pages = 0;
    std::fclose(f);
  }
  return static_cast<double>(pages) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
}

std::string mb(double bytes) { return std::to_string(static_cast<long long>(std::ceil(bytes / kMiB))) + " MB"; }
}  // namespace

double gl_context_address_space() { return kContextBytes + kPerRasterThread * raster_threads(); }

std::string address_space_shortfall(double bytes, const std::string& what) {
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return "";
  const double allowed = static_cast<double>(limit.rlim_cur), used = mapped_bytes();
  if (used + bytes <= allowed) return "";
  const double least = used + bytes;
  return "ulimit -v " + std::to_string(limit.rlim_cur / 1024) + " (" + mb(allowed) + " of address space, " + mb(used) +
         " in use) leaves too little for " + what + " (about " + mb(bytes) + "): raise it to at least ulimit -v " +
         std::to_string(static_cast<long long>(std::ceil(least / 1024)));
}

void require_framebuffer_space(int width, int height, int samples) {
  const std::string shortfall = address_space_shortfall(
      (20.0 + 8.0 * samples) * width * height,
      "the " + std::to_string(width) + "x" + std::to_string(height) + " framebuffer with " + std::to_string(samples) +
          " samples");
  if (!shortfall.empty()) throw RenderError(shortfall);
}

std::unique_ptr<GlContext> create_gl_context(GlBackend backend) {
  const std::string shortfall = address_space_shortfall(
      gl_context_address_space(), "an OpenGL context with " + std::to_string(raster_threads()) + " llvmpipe threads");
  if (!shortfall.empty()) throw RenderError(shortfall + " (or set LP_NUM_THREADS=0)");
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
