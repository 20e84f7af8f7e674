#include "gl_program.h"

#include <cstdio>
#include <vector>

#include "render_error.h"

namespace clothsim::gl {

namespace {

std::string info_log(GLuint object, bool is_program) {
  GLint length = 0;
  if (is_program) glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
  else glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<std::size_t>(length > 1 ? length : 1), '\0');
  if (is_program) glGetProgramInfoLog(object, length, nullptr, log.data());
  else glGetShaderInfoLog(object, length, nullptr, log.data());
  std::string text(log.data());
  for (char& c : text) if (c == '\n') c = ' ';  // one-line errors
  return text;
}

GLuint compile(GLenum stage, const std::string& source, const std::string& name) {
  GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = info_log(shader, false);
    glDeleteShader(shader);
    throw RenderError("cannot compile the " + name +
                      (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") + " shader: " + log);
  }
  return shader;
}

const char* error_name(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "unknown";
  }
}

}  // namespace

GLuint build_program(const std::string& name, const std::string& vertex_source,
                     const std::string& fragment_source) {
  const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source, name);
  GLuint fragment = 0;
  try {
    fragment = compile(GL_FRAGMENT_SHADER, fragment_source, name);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);    // flagged; freed with the program
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = info_log(program, true);
    glDeleteProgram(program);
    throw RenderError("cannot link the " + name + " program: " + log);
  }
  return program;
}

void check_gl(const std::string& what) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {}  // drain, so the next check starts clean
  char code[16];
  std::snprintf(code, sizeof code, "0x%04X", error);
  throw RenderError(std::string("OpenGL error ") + code + " (" + error_name(error) + ") while " + what);
}

}  // namespace clothsim::gl
