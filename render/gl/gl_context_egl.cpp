// The EGL backend: an OpenGL 3.3 core context with no surface at all (EGL_KHR_surfaceless_context;
// the renderer draws into its own FBOs), on the first display that gives one:
//   1. a GPU through the device platform (EGL_EXT_platform_device: NVIDIA's driver, Mesa's
//      hardware drivers), skipping Mesa's software device,
//   2. Mesa's surfaceless platform (EGL_MESA_platform_surfaceless: llvmpipe, no GPU, no display),
//   3. any device left (Mesa's software device is llvmpipe as well).
// No X server or window system is touched, so it works under ssh, cron, Slurm and CI.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "gl_context.h"
#include "render_error.h"

namespace clothsim {

namespace {

std::string egl_error() {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
  return code;
}

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

struct Candidate {
  EGLDisplay display;
  std::string description;
};

// The displays to try, in the order of the header comment.
std::vector<Candidate> candidate_displays(std::string& why_none) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client) {
    why_none = "libEGL offers no client extensions (EGL 1.5 or EGL_EXT_client_extensions needed)";
    return {};
  }
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) {
    why_none = "libEGL has no eglGetPlatformDisplayEXT";
    return {};
  }
  std::vector<Candidate> hardware, software;
  if (has_extension(client, "EGL_EXT_platform_device")) {
    const auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    const auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (query_devices && query_devices(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = query_device_string ? query_device_string(devices[i], EGL_EXTENSIONS) : nullptr;
        const bool is_software = has_extension(ext, "EGL_MESA_device_software");
        EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (d == EGL_NO_DISPLAY) continue;
        (is_software ? software : hardware).push_back({d, "egl (device " + std::to_string(i) + ")"});
      }
    }
  }
  std::vector<Candidate> all = hardware;
  if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (d != EGL_NO_DISPLAY) all.push_back({d, "egl (surfaceless)"});
  }
  all.insert(all.end(), software.begin(), software.end());
  if (all.empty())
    why_none = "no EGL device or surfaceless display (EGL_EXT_platform_device, EGL_MESA_platform_surfaceless)";
  return all;
}

class EglContext final : public GlContext {
 public:
  EglContext() {
    std::string why;
    const std::vector<Candidate> candidates = candidate_displays(why);
    for (const Candidate& c : candidates) {
      if (try_display(c, why)) return;
    }
    throw RenderError("cannot create an EGL OpenGL 3.3 core context: " + why);
  }
  ~EglContext() override {
    // Release first if ours is current on this thread: a current context is not destroyed
    // until released, and eglTerminate would leave it dangling.
    if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    // The display is left initialised: EGL displays are per process and shared by every
    // context on them; terminating it would destroy another Renderer's context.
  }

  void make_current() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw RenderError("eglMakeCurrent failed (EGL error " + egl_error() + ")");
  }
  void release() noexcept override { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }
  void* proc_address(const char* name) override { return reinterpret_cast<void*>(eglGetProcAddress(name)); }
  std::string description() const override { return description_; }

 private:
  bool try_display(const Candidate& c, std::string& why) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(c.display, &major, &minor)) {
      why = c.description + ": eglInitialize failed (EGL error " + egl_error() + ")";
      return false;
    }
    const char* ext = eglQueryString(c.display, EGL_EXTENSIONS);
    if (!has_extension(ext, "EGL_KHR_surfaceless_context")) {
      why = c.description + ": no EGL_KHR_surfaceless_context";
      return false;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
      why = c.description + ": no desktop OpenGL (eglBindAPI)";
      return false;
    }
    // Any config that renders desktop GL; the surfaceless platform offers pbuffer configs
    // only (the default EGL_SURFACE_TYPE, a window, matches none). No surface is created.
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                        EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(c.display, config_attributes, &config, 1, &configs) || configs < 1) {
      why = c.description + ": no EGL config for desktop OpenGL";
      return false;
    }
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_NONE};
    EGLContext context = eglCreateContext(c.display, config, EGL_NO_CONTEXT, context_attributes);
    if (context == EGL_NO_CONTEXT) {
      why = c.description + ": no OpenGL 3.3 core context (EGL error " + egl_error() + ")";
      return false;
    }
    display_ = c.display;
    context_ = context;
    description_ = c.description;
    return true;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::string description_;
};

}  // namespace

std::unique_ptr<GlContext> create_egl_context() { return std::make_unique<EglContext>(); }

}  // namespace clothsim
