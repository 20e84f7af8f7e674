// Uniforms by name, buffer uploads and vertex attributes: the few GL calls every pass of the
// renderer makes, in one line each (a few dozen uniform lookups a frame: cheaper than the
// clarity they buy).
#pragma once

#include <array>
#include <vector>

#include "gl_functions.h"
#include "gl_math.h"

namespace clothsim::gl {

inline void set(GLuint p, const char* name, float v) { glUniform1f(glGetUniformLocation(p, name), v); }
inline void set(GLuint p, const char* name, int v) { glUniform1i(glGetUniformLocation(p, name), v); }
inline void set(GLuint p, const char* name, Vec3 v) { glUniform3f(glGetUniformLocation(p, name), v.x, v.y, v.z); }
inline void set(GLuint p, const char* name, const std::array<float, 3>& c) {
  glUniform3f(glGetUniformLocation(p, name), c[0], c[1], c[2]);
}
inline void set(GLuint p, const char* name, float a, float b) { glUniform2f(glGetUniformLocation(p, name), a, b); }
inline void set(GLuint p, const char* name, const Mat4& m) {
  glUniformMatrix4fv(glGetUniformLocation(p, name), 1, GL_FALSE, m.data());
}
// A mesh's placement in the world: offset, then uniform scale (u_placement).
inline void set_placement(GLuint p, Vec3 offset, float scale) {
  glUniform4f(glGetUniformLocation(p, "u_placement"), offset.x, offset.y, offset.z, scale);
}

template <class T>
void upload(GLenum target, GLuint buffer, const std::vector<T>& data) {
  glBindBuffer(target, buffer);
  glBufferData(target, static_cast<GLsizeiptr>(data.size() * sizeof(T)), data.data(), GL_STREAM_DRAW);
}

inline void attribute(GLuint index, GLuint buffer, int components) {
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glEnableVertexAttribArray(index);
  glVertexAttribPointer(index, components, GL_FLOAT, GL_FALSE, 0, nullptr);
}

}  // namespace clothsim::gl
