#include "render/gl/gl_program.h"

#include <gtest/gtest.h>

#include <string>

#include "render/renderer.h"

namespace clothsim {
namespace {

const char* const kVertex = "#version 330 core\nvoid main() { gl_Position = vec4(0.0); }\n";
const char* const kFragment = "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n";

// The Renderer's context, made current on this thread: GL calls below go to it.
Renderer& context() {
  static Renderer r;
  r.make_current();
  return r;
}

std::string error_of(const std::string& vertex, const std::string& fragment) {
  context();
  try {
    gl::build_program("probe", vertex, fragment);
  } catch (const RenderError& e) {
    return e.what();
  }
  return "(built)";
}

TEST(GlProgram, BuildsAValidProgram) {
  context();
  const GLuint program = gl::build_program("probe", kVertex, kFragment);
  EXPECT_NE(program, 0u);
  EXPECT_TRUE(glIsProgram(program));
  glDeleteProgram(program);
}

TEST(GlProgram, ACompileErrorNamesTheProgramAndStageOnOneLine) {
  const std::string message = error_of(kVertex, "#version 330 core\nvoid main() { this is not glsl }\n");
  EXPECT_NE(message.find("cannot compile the probe fragment shader"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(error_of("#version 330 core\nvoid main() { gl_Position = 1; }\n", kFragment).find("vertex"),
            std::string::npos);
}

TEST(GlProgram, ALinkErrorNamesTheProgram) {
  // A stage without main() compiles, but cannot be linked.
  const std::string message = error_of(kVertex, "#version 330 core\nout vec4 c;\nvoid helper() { c = vec4(1.0); }\n");
  EXPECT_NE(message.find("cannot link the probe program"), std::string::npos) << message;
}

TEST(GlProgram, CheckGlTurnsAnErrorIntoARenderErrorAndClearsIt) {
  context();
  glBindBuffer(GL_ARRAY_BUFFER, 0xFFFFFF);  // not a name from glGenBuffers: GL_INVALID_OPERATION in core
  try {
    gl::check_gl("binding a bad buffer");
    ADD_FAILURE() << "no error reported";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("while binding a bad buffer"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(gl::check_gl("nothing"));
}

}  // namespace
}  // namespace clothsim
