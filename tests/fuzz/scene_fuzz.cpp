#include "scene_fuzz.h"

#include <cmath>
#include <exception>
#include <typeinfo>

#include "core/model/model.h"
#include "scene/build_model.h"
#include "scene/echo.h"
#include "scene/memory_estimate.h"
#include "scene/run_bounds.h"
#include "scene/scene_parser.h"

namespace clothsim::fuzz {
namespace {

constexpr const char* kSource = "fuzz.yaml";
constexpr const char* kSetPrefix = "#--set ";

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// \n, \t, \\ and \xHH; any other backslash stays as it is.
std::string unescape(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\\' || i + 1 == text.size()) {
      out += text[i];
      continue;
    }
    const char c = text[i + 1];
    if (c == 'n') out += '\n', ++i;
    else if (c == 't') out += '\t', ++i;
    else if (c == '\\') out += '\\', ++i;
    else if (c == 'x' && i + 3 < text.size() && hex_digit(text[i + 2]) >= 0 && hex_digit(text[i + 3]) >= 0) {
      out += static_cast<char>(hex_digit(text[i + 2]) * 16 + hex_digit(text[i + 3]));
      i += 3;
    } else {
      out += text[i];
    }
  }
  return out;
}

bool finite(const Eigen::Matrix3Xd& m) { return m.allFinite(); }

template <typename T>
double bytes_of(const std::vector<T>& v) {
  return static_cast<double>(v.capacity() * sizeof(T));
}

// What the Model built from a validated `scene` must be; "" when it is.
std::string model_problem(const SceneDef& scene, const Model& m) {
  const long P = static_cast<long>(scene.cloth.nx) * scene.cloth.ny;
  const long B = P + static_cast<long>(scene.spheres.size());
  if (m.num_particles != P || m.num_bodies() != B || m.grid_nx != scene.cloth.nx || m.grid_ny != scene.cloth.ny)
    return "model: body counts differ from the scene";
  if (m.mass.size() != B || m.initial_inv_mass.size() != B || static_cast<long>(m.gravity_on.size()) != B ||
      m.initial_x.cols() != B || m.initial_v.cols() != B)
    return "model: a per-body array has the wrong length";
  if (!finite(m.initial_x) || !finite(m.initial_v)) return "model: non-finite initial position or velocity";
  for (long b = 0; b < B; ++b)
    if (!(m.initial_inv_mass[b] >= 0.0) || !std::isfinite(m.initial_inv_mass[b]) || !(m.mass[b] > 0.0))
      return "model: body " + std::to_string(b) + " has a bad mass or inverse mass";

  const Springs& s = m.springs;
  const std::size_t S = s.size();
  if (static_cast<std::int64_t>(S) != spring_count(scene.cloth)) return "model: spring_count() differs from the springs built";
  if (s.b.size() != S || s.rest.size() != S || s.ks.size() != S || s.kd.size() != S || s.type.size() != S)
    return "model: spring arrays of different lengths";
  for (std::size_t k = 0; k < S; ++k) {
    if (!(0 <= s.a[k] && s.a[k] < s.b[k] && s.b[k] < P)) return "model: spring " + std::to_string(k) + " indices out of range";
    if (!(s.rest[k] > 0.0) || !std::isfinite(s.rest[k]))
      return "model: spring " + std::to_string(k) + " rest length " + std::to_string(s.rest[k]) + " is not finite and > 0";
    if (!(s.ks[k] >= 0.0) || !std::isfinite(s.ks[k]) || !(s.kd[k] >= 0.0) || !std::isfinite(s.kd[k]))
      return "model: spring " + std::to_string(k) + " stiffness or damping not finite and >= 0";
  }
  if (m.triangles.size() % 3 != 0) return "model: triangle indices not a multiple of 3";
  for (std::uint32_t t : m.triangles)
    if (t >= static_cast<std::uint32_t>(P)) return "model: triangle index out of range";
  for (std::size_t k = 0; k < m.timeline.size(); ++k) {
    const TimedAction& a = m.timeline[k];
    if (a.body < 0 || a.body >= B || !std::isfinite(a.t) || (k > 0 && a.t < m.timeline[k - 1].t))
      return "model: timeline action " + std::to_string(k) + " out of range or out of order";
  }
  // The energy scale may overflow to +inf (particle_mass: 1e308): the energy bound then never
  // fires and divergence is found by non-finite values alone. It must not be NaN or <= 0.
  if (!(m.energy_scale > 0.0)) return "model: energy scale not > 0";

  // What the arrays hold (capacity: memory taken, used or not) against the estimate.
  const double held = 8.0 * (m.mass.size() + m.initial_inv_mass.size() + m.initial_x.size() + m.initial_v.size()) +
                      bytes_of(m.gravity_on) + bytes_of(s.a) + bytes_of(s.b) + bytes_of(s.rest) + bytes_of(s.ks) +
                      bytes_of(s.kd) + bytes_of(s.type) + bytes_of(m.sphere_radius) + bytes_of(m.sphere_restitution) +
                      bytes_of(m.sphere_friction) + bytes_of(m.sphere_kinematic) + bytes_of(m.timeline) +
                      bytes_of(m.triangles);
  if (held > model_bytes(scene))
    return "model: holds " + std::to_string(held) + " bytes, more than model_bytes() estimates (" +
           std::to_string(model_bytes(scene)) + ")";
  return "";
}

// A refusal as the contract wants it: one line, naming the file, of bounded length.
std::string message_problem(const std::string& message) {
  for (char c : message)
    if (static_cast<unsigned char>(c) < 0x20) return "error message holds a control byte: " + excerpt(message, 200);
  if (message.rfind(std::string(kSource) + ":", 0) != 0) return "error message does not start with the file: " + excerpt(message, 200);
  if (message.size() > kMaxMessage)
    return "error message of " + std::to_string(message.size()) + " bytes: " + excerpt(message, 200);
  return "";
}

}  // namespace

SceneInput split_input(const std::uint8_t* data, std::size_t size) {
  SceneInput in;
  in.text.assign(reinterpret_cast<const char*>(data), size);
  const std::string prefix = kSetPrefix;
  for (std::size_t start = 0; start < in.text.size();) {
    std::size_t end = in.text.find('\n', start);
    if (end == std::string::npos) end = in.text.size();
    if (in.text.compare(start, prefix.size(), prefix) == 0 && end >= start + prefix.size())
      in.overrides.push_back(unescape(in.text.substr(start + prefix.size(), end - start - prefix.size())));
    start = end + 1;
  }
  return in;
}

std::string scene_input_problem(const std::uint8_t* data, std::size_t size) {
  const SceneInput in = split_input(data, size);
  SceneDef scene;
  try {
    scene = parse_scene(in.text, kSource, in.overrides);
  } catch (const SceneError& e) {
    return message_problem(e.what());
  } catch (const std::exception& e) {
    return std::string("parse_scene threw ") + typeid(e).name() + ", not a SceneError: " + excerpt(e.what(), 200);
  } catch (...) {
    return "parse_scene threw something that is not a std::exception";
  }

  const std::string too_long = run_bounds_problem(scene.duration, scene.dt, scene.render.fps);
  if (!too_long.empty()) return "validated past the run bounds: " + too_long;
  if (model_bytes(scene) > kFuzzMemory) return "";  // refused by the memory budget, as the CLI would

  try {
    const Model model = build_model(scene);
    return model_problem(scene, model);
  } catch (const std::exception& e) {
    return std::string("build_model threw ") + typeid(e).name() + " on a validated scene: " + excerpt(e.what(), 200);
  }
}

}  // namespace clothsim::fuzz
