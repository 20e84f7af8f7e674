// The GL backends (gl_context.h): names, the environment variable, and that EGL and OSMesa
// give the same pictures (both are llvmpipe here; on NVIDIA, EGL is the GPU and the
// golden tolerance is what must hold).
#include "render/gl/gl_context.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "render/image_diff.h"
#include "render/renderer.h"
#include "render/synthetic_frames.h"

namespace clothsim {
namespace {

bool built(GlBackend b) {
  for (GlBackend x : built_gl_backends())
    if (x == b) return true;
  return false;
}

TEST(GlContext, TheThreeNamesParseAndOthersDoNot) {
  EXPECT_EQ(parse_gl_backend("auto"), GlBackend::automatic);
  EXPECT_EQ(parse_gl_backend("egl"), GlBackend::egl);
  EXPECT_EQ(parse_gl_backend("osmesa"), GlBackend::osmesa);
  EXPECT_FALSE(parse_gl_backend("EGL"));
  EXPECT_FALSE(parse_gl_backend("glx"));
  for (GlBackend b : {GlBackend::automatic, GlBackend::egl, GlBackend::osmesa})
    EXPECT_EQ(parse_gl_backend(gl_backend_name(b)), b);
}

TEST(GlContext, TheEnvironmentVariableChoosesAndABadValueIsAnError) {
  const char* saved = std::getenv("CLOTHSIM_GL");
  const std::string restore = saved ? saved : "";
  unsetenv("CLOTHSIM_GL");
  EXPECT_EQ(gl_backend_from_environment(), GlBackend::automatic);
  setenv("CLOTHSIM_GL", "osmesa", 1);
  EXPECT_EQ(gl_backend_from_environment(), GlBackend::osmesa);
  setenv("CLOTHSIM_GL", "vulkan", 1);
  try {
    gl_backend_from_environment();
    ADD_FAILURE() << "CLOTHSIM_GL=vulkan accepted";
  } catch (const RenderError& e) {
    EXPECT_STREQ(e.what(), "CLOTHSIM_GL=vulkan: expected auto, egl or osmesa");
  }
  if (saved) setenv("CLOTHSIM_GL", restore.c_str(), 1);
  else unsetenv("CLOTHSIM_GL");
}

// This machine's build (tools/install-deps.sh installs both) has both backends; a build on a
// machine without one of them still has this test telling which it lacks.
TEST(GlContext, BothBackendsAreBuiltHere) {
  EXPECT_TRUE(built(GlBackend::egl));
  EXPECT_TRUE(built(GlBackend::osmesa));
}

TEST(GlContext, EachBackendGivesACoreContextAndSaysWhichItIs) {
  for (GlBackend b : built_gl_backends()) {
    Renderer r(b);
    EXPECT_EQ(r.gl_backend().rfind(gl_backend_name(b), 0), 0u) << r.gl_backend();
    EXPECT_NE(r.gl_version().find("Core Profile"), std::string::npos) << r.gl_version();
    EXPECT_FALSE(r.gl_vendor().empty());
    EXPECT_FALSE(r.gl_renderer().empty());
  }
}

TEST(GlContext, AutoTakesEglFirst) {
  if (!built(GlBackend::egl)) GTEST_SKIP() << "built without EGL";
  EXPECT_EQ(Renderer(GlBackend::automatic).gl_backend().rfind("egl", 0), 0u);
}

// The same frames through both backends, alternating on one thread (each backend's entry
// points are its own): within the golden-image tolerance, and each backend repeats itself.
TEST(GlContext, EglAndOsmesaImagesAgreeWithinTheImgdiffTolerance) {
  ASSERT_TRUE(built(GlBackend::egl) && built(GlBackend::osmesa));
  Renderer egl(GlBackend::egl), osmesa(GlBackend::osmesa);
  RenderFrame draped = testing::draped_sheet_frame(320, 180);
  draped.overlay_lines = {"symplectic_euler", "t = 1.000 s"};
  const DiffTolerance tolerance;
  const Image first = egl.render(draped);
  const Image other = osmesa.render(draped);
  const DiffStats stats = compare_images(first, other, tolerance.pixel_threshold);
  EXPECT_TRUE(within_tolerance(stats, tolerance)) << "rms " << stats.rms << ", max " << stats.max;
  EXPECT_EQ(egl.render(draped).rgba, first.rgba);
  EXPECT_EQ(osmesa.render(draped).rgba, other.rgba);
}

}  // namespace
}  // namespace clothsim
