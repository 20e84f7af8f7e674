#include "render/gl/shaders.h"

#include <gtest/gtest.h>

#include "render/gl/gl_program.h"
#include "render/renderer.h"

namespace clothsim {
namespace {

TEST(Shaders, EveryProgramCompilesAndLinksOnTheCoreProfile) {
  static Renderer r;
  r.make_current();  // its context, current on this thread
  const struct {
    const char* name;
    const std::string& vertex;
    const std::string& fragment;
  } programs[] = {{"cloth", shaders::kSurfaceVertex, shaders::kClothFragment},
                  {"sphere", shaders::kSurfaceVertex, shaders::kSphereFragment},
                  {"ground", shaders::kSurfaceVertex, shaders::kGroundFragment},
                  {"shadow", shaders::kShadowVertex, shaders::kShadowFragment},
                  {"background", shaders::kBackgroundVertex, shaders::kBackgroundFragment},
                  {"flat", shaders::kFlatVertex, shaders::kFlatFragment}};
  for (const auto& p : programs) {
    EXPECT_EQ(p.vertex.rfind("#version 330 core\n", 0), 0u) << p.name;
    EXPECT_EQ(p.fragment.rfind("#version 330 core\n", 0), 0u) << p.name;
    GLuint program = 0;
    EXPECT_NO_THROW(program = gl::build_program(p.name, p.vertex, p.fragment)) << p.name;
    glDeleteProgram(program);
  }
}

}  // namespace
}  // namespace clothsim
