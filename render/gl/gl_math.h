// The little linear algebra the renderer needs: 3-vectors and column-major 4x4 matrices
// laid out as OpenGL expects (glUniformMatrix4fv with transpose = GL_FALSE).
// Float only, no SIMD: the same inputs give the same bits on every x86-64 machine.
#pragma once

#include <array>
#include <cmath>

namespace clothsim::gl {

struct Vec3 {
  float x = 0.f, y = 0.f, z = 0.f;
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) {
  const float n = length(a);
  return n > 0.f ? a * (1.f / n) : Vec3{0.f, 1.f, 0.f};
}
inline Vec3 to_vec3(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

// m[column * 4 + row], as GLSL's mat4.
struct Mat4 {
  std::array<float, 16> m{};
  float& at(int row, int col) { return m[col * 4 + row]; }
  float at(int row, int col) const { return m[col * 4 + row]; }
  const float* data() const { return m.data(); }
};

inline Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) {
      float s = 0.f;
      for (int k = 0; k < 4; ++k) s += a.at(row, k) * b.at(k, col);
      r.at(row, col) = s;
    }
  return r;
}

// World -> eye: the camera at `eye` looks at `target`, `up` roughly up (gluLookAt).
inline Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up) {
  const Vec3 f = normalize(target - eye);
  Vec3 s = cross(f, up);
  if (length(s) < 1e-6f) s = cross(f, std::fabs(f.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 0, 1});
  s = normalize(s);
  const Vec3 u = cross(s, f);
  Mat4 r;
  r.at(0, 0) = s.x;  r.at(0, 1) = s.y;  r.at(0, 2) = s.z;  r.at(0, 3) = -dot(s, eye);
  r.at(1, 0) = u.x;  r.at(1, 1) = u.y;  r.at(1, 2) = u.z;  r.at(1, 3) = -dot(u, eye);
  r.at(2, 0) = -f.x; r.at(2, 1) = -f.y; r.at(2, 2) = -f.z; r.at(2, 3) = dot(f, eye);
  r.at(3, 3) = 1.f;
  return r;
}

// Eye -> clip for a vertical field of view (gluPerspective).
inline Mat4 perspective(float fov_y_deg, float aspect, float near_z, float far_z) {
  const float f = 1.f / std::tan(fov_y_deg * 3.14159265f / 360.f);
  Mat4 r;
  r.at(0, 0) = f / aspect;
  r.at(1, 1) = f;
  r.at(2, 2) = (far_z + near_z) / (near_z - far_z);
  r.at(2, 3) = 2.f * far_z * near_z / (near_z - far_z);
  r.at(3, 2) = -1.f;
  return r;
}

}  // namespace clothsim::gl
