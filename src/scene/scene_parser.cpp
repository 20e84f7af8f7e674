// The scene parser: text -> YAML tree (+ --set overrides) -> SceneDef, validating as it
// reads. Every field is read by one typed accessor that knows its dotted key and its node's
// line, so every error can say where it is; every map is checked for keys it does not know.
#include "scene_parser.h"
#include "view/vertex_fields.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "echo.h"
#include "names.h"
#include "run_bounds.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <sys/stat.h>

namespace clothsim {

namespace {
// One line whatever the input: the file name and the key are user text too (a key can be a
// megabyte of junk, a path can hold a newline), so both are echoed as excerpts.
std::string format_error(const std::string& file, int line, const std::string& key,
                         const std::string& what) {
  std::string out = excerpt(file, 256);
  if (line > 0) out += ":" + std::to_string(line);
  if (!key.empty()) out += ": " + excerpt(key);
  return out + ": " + what;
}
}  // namespace

SceneError::SceneError(std::string file_, int line_, std::string key_, const std::string& what)
    : std::runtime_error(format_error(file_, line_, key_, what)),
      file(std::move(file_)),
      line(line_),
      key(std::move(key_)) {}

namespace {

std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

const char* type_name(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map: return "a map";
    case YAML::NodeType::Sequence: return "a list";
    case YAML::NodeType::Scalar: return "a scalar";
    case YAML::NodeType::Null: return "nothing (null)";
    default: return "nothing";
  }
}

// Reads one scene's YAML tree into a SceneDef. Holds the file name and which dotted keys
// came from --set, so an error in an overridden value names the override, not a line.
class Reader {
 public:
  Reader(std::string file, std::map<std::string, std::string> overrides, bool bound_run)
      : file_(std::move(file)), overrides_(std::move(overrides)), bound_run_(bound_run) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    // A value under an override ("gravity[1]" under --set gravity=[0,.nan,0]), the override
    // itself, or a map the override reaches into: the error names the override, not a line.
    for (const auto& [path, text] : overrides_)
      if (key == path || key.rfind(path + ".", 0) == 0 || key.rfind(path + "[", 0) == 0 ||
          path.rfind(key + ".", 0) == 0)
        throw SceneError(file_, 0, "--set " + text, what);
    const int line = node.IsDefined() && !node.Mark().is_null() ? node.Mark().line + 1 : 0;
    throw SceneError(file_, line, key, what);
  }

  // Checks that `node` is a map whose keys are all in `allowed`, with no duplicates.
  void expect_map(const YAML::Node& node, const std::string& path,
                  std::initializer_list<const char*> allowed) const {
    if (!node.IsMap()) fail(node, path, std::string("expected a map, got ") + type_name(node));
    std::set<std::string> seen;
    for (const auto& kv : node) {
      const std::string k = kv.first.Scalar();
      bool known = false;
      for (const char* a : allowed) known = known || k == a;
      if (!known) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(kv.first, join(path, k), "unknown key (expected one of: " + list + ")");
      }
      if (!seen.insert(k).second) fail(kv.first, join(path, k), "duplicate key");
    }
  }

  double number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, std::string("expected a number, got ") + type_name(n));
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected a number, got " + in_quotes(n.Scalar()));
    }
    if (!std::isfinite(v)) fail(n, key, "expected a finite number, got " + in_quotes(n.Scalar()));
    return v;
  }

  int integer(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, std::string("expected an integer, got ") + type_name(n));
    try {
      return n.as<int>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected an integer, got " + in_quotes(n.Scalar()));
    }
  }

  bool boolean(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, std::string("expected true or false, got ") + type_name(n));
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected true or false, got " + in_quotes(n.Scalar()));
    }
  }

  std::string string(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, std::string("expected a string, got ") + type_name(n));
    return n.Scalar();
  }

  Vec3 vec3(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() != 3)
      fail(n, key, "expected a list of 3 numbers [x, y, z]");
    return Vec3(number(n[0], key + "[0]"), number(n[1], key + "[1]"), number(n[2], key + "[2]"));
  }

  // Range checks: `lo`/`hi` bounds, inclusive unless stated; messages give the allowed range.
  double in_range(const YAML::Node& n, const std::string& key, double lo, double hi,
                  bool lo_open = false) const {
    const double v = number(n, key);
    const bool ok = (lo_open ? v > lo : v >= lo) && v <= hi;
    if (!ok) {
      std::ostringstream msg;
      msg << "value " << excerpt(n.Scalar()) << " out of range: must be " << (lo_open ? "> " : ">= ") << lo;
      if (std::isfinite(hi)) msg << " and <= " << hi;
      fail(n, key, msg.str());
    }
    return v;
  }
  double positive(const YAML::Node& n, const std::string& key) const {
    return in_range(n, key, 0.0, INFINITY, true);
  }
  double non_negative(const YAML::Node& n, const std::string& key) const {
    return in_range(n, key, 0.0, INFINITY);
  }
  int int_in_range(const YAML::Node& n, const std::string& key, int lo, int hi) const {
    const int v = integer(n, key);
    if (v < lo || v > hi)
      fail(n, key, "value " + excerpt(n.Scalar()) + " out of range: must be from " + std::to_string(lo) +
                       " to " + std::to_string(hi));
    return v;
  }

  // Calls `read(value_node, dotted_key)` if `key` is present in `map`.
  void optional(const YAML::Node& map, const std::string& path, const char* key,
                const std::function<void(const YAML::Node&, const std::string&)>& read) const {
    const YAML::Node n = map[key];
    if (n.IsDefined()) read(n, join(path, key));
  }

  SceneDef scene(const YAML::Node& root) const;

 private:
  ClothDef cloth(const YAML::Node& n, const std::string& path) const;
  void grid_geometry(const YAML::Node& n, const std::string& path, const ClothDef& c) const;
  std::optional<SpringParams> springs(const YAML::Node& n, const std::string& path) const;
  std::vector<GridSelection> selection(const YAML::Node& n, const std::string& key, const ClothDef& c,
                                       bool none_allowed) const;
  GridSelection selection_item(const YAML::Node& n, const std::string& key, const ClothDef& c) const;
  void index_range(const YAML::Node& n, const std::string& key, int size, int& lo, int& hi) const;
  SphereDef sphere(const YAML::Node& n, const std::string& path) const;
  RenderDef render(const YAML::Node& n, const std::string& path) const;
  ImplicitDef implicit(const YAML::Node& n, const std::string& path) const;

  std::string file_;
  std::map<std::string, std::string> overrides_;  // dotted key -> "KEY=VALUE" as typed
  bool bound_run_;  // check duration / dt and the frame count (run_bounds.h)
};

SceneDef Reader::scene(const YAML::Node& root) const {
  SceneDef s;
  s.source = file_;
  expect_map(root, "", {"name", "duration", "dt", "integrator", "gravity", "air_drag", "cloth",
                        "spheres", "ground", "collision", "events", "render", "implicit",
                        "divergence"});
  optional(root, "", "name", [&](auto& n, auto& k) {
    s.name = string(n, k);
    if (const std::string problem = name_problem(s.name); !problem.empty()) fail(n, k, problem);  // names.h
  });
  optional(root, "", "duration", [&](auto& n, auto& k) { s.duration = non_negative(n, k); });
  optional(root, "", "dt", [&](auto& n, auto& k) { s.dt = positive(n, k); });
  optional(root, "", "integrator", [&](auto& n, auto& k) {
    const auto kind = parse_integrator(string(n, k));
    if (!kind) fail(n, k, "unknown integrator " + in_quotes(n.Scalar()) + " (expected one of: " + integrator_names_joined() + ")");
    s.integrator = *kind;
  });
  optional(root, "", "gravity", [&](auto& n, auto& k) { s.gravity = vec3(n, k); });
  optional(root, "", "air_drag", [&](auto& n, auto& k) { s.air_drag = non_negative(n, k); });
  const YAML::Node cloth_node = root["cloth"];
  if (!cloth_node.IsDefined()) fail(root, "cloth", "missing: every scene has a cloth (see docs/scenes.md)");
  s.cloth = cloth(cloth_node, "cloth");
  optional(root, "", "spheres", [&](auto& n, auto& k) {
    if (!n.IsSequence()) fail(n, k, std::string("expected a list of spheres, got ") + type_name(n));
    for (std::size_t i = 0; i < n.size(); ++i) s.spheres.push_back(sphere(n[i], k + "." + std::to_string(i)));
  });
  optional(root, "", "ground", [&](auto& n, auto& k) {
    expect_map(n, k, {"height", "restitution", "friction"});
    GroundDef g;
    optional(n, k, "height", [&](auto& v, auto& kk) { g.height = number(v, kk); });
    optional(n, k, "restitution", [&](auto& v, auto& kk) { g.restitution = in_range(v, kk, 0, 1); });
    optional(n, k, "friction", [&](auto& v, auto& kk) { g.friction = non_negative(v, kk); });
    s.ground = g;
  });
  optional(root, "", "collision", [&](auto& n, auto& k) {
    expect_map(n, k, {"margin", "sphere_sphere", "sphere_restitution"});
    optional(n, k, "margin", [&](auto& v, auto& kk) { s.collision.margin = non_negative(v, kk); });
    optional(n, k, "sphere_sphere", [&](auto& v, auto& kk) { s.collision.sphere_sphere = boolean(v, kk); });
    optional(n, k, "sphere_restitution", [&](auto& v, auto& kk) { s.collision.sphere_restitution = in_range(v, kk, 0, 1); });
  });
  optional(root, "", "events", [&](auto& n, auto& k) {
    if (!n.IsSequence()) fail(n, k, std::string("expected a list of events, got ") + type_name(n));
    for (std::size_t i = 0; i < n.size(); ++i) {
      const std::string p = k + "." + std::to_string(i);
      expect_map(n[i], p, {"t", "pin", "unpin"});
      EventDef e;
      if (!n[i]["t"].IsDefined()) fail(n[i], p + ".t", "missing: an event needs its time t");
      e.t = non_negative(n[i]["t"], p + ".t");
      optional(n[i], p, "pin", [&](auto& v, auto& kk) { e.pin = selection(v, kk, s.cloth, false); });
      optional(n[i], p, "unpin", [&](auto& v, auto& kk) { e.unpin = selection(v, kk, s.cloth, false); });
      if (e.pin.empty() && e.unpin.empty()) fail(n[i], p, "an event needs pin or unpin");
      s.events.push_back(e);
    }
  });
  optional(root, "", "render", [&](auto& n, auto& k) { s.render = render(n, k); });
  optional(root, "", "implicit", [&](auto& n, auto& k) { s.implicit = implicit(n, k); });
  optional(root, "", "divergence", [&](auto& n, auto& k) {
    expect_map(n, k, {"max_strain", "max_energy_factor"});
    optional(n, k, "max_strain", [&](auto& v, auto& kk) { s.divergence.max_strain = positive(v, kk); });
    optional(n, k, "max_energy_factor", [&](auto& v, auto& kk) { s.divergence.max_energy_factor = positive(v, kk); });
  });
  // Steps and frames, bounded before anything is allocated for them (run_bounds.h), unless the
  // caller replaces duration or dt and bounds the result itself. The error names the key at
  // fault: dt (or duration, when --set gave it or the file has no dt) for too many steps,
  // duration (or render.fps, when the file has no duration) for too many frames.
  if (bound_run_) {
    const std::string too_long = run_bounds_problem(s.duration, s.dt, s.render.fps);
    if (!too_long.empty()) {
      const bool by_steps = !(s.duration / s.dt <= kMaxSteps);
      const bool has_duration = root["duration"].IsDefined();
      if (by_steps && root["dt"].IsDefined() && !(has_duration && overrides_.count("duration")))
        fail(root["dt"], "dt", too_long);
      if (!by_steps && !has_duration && root["render"].IsMap() && root["render"]["fps"].IsDefined())
        fail(root["render"]["fps"], "render.fps", too_long);
      fail(root["duration"], "duration", too_long);
    }
  }
  return s;
}

// The grid must be representable: every particle within kMaxReach of the origin (past it,
// centre + size overflows or loses the spacing), and neighbours at least kMinSpacing apart
// and 1e-9 of that reach (closer, their distance rounds to 0 or underflows when squared, and
// the first spring force is 0/0). Found by the fuzzer (tests/fuzz/regressions/).
void Reader::grid_geometry(const YAML::Node& n, const std::string& path, const ClothDef& c) const {
  constexpr double kMaxReach = 1e9, kMinSpacing = 1e-6;  // m
  const bool xz = c.plane == ClothPlane::XZ;
  const double reach_x = std::abs(c.center.x()) + 0.5 * c.size_x + std::abs(c.initial_stretch);
  const double reach_2 = std::abs(xz ? c.center.z() : c.center.y()) + 0.5 * c.size_y;
  const double reach = std::max({reach_x, reach_2, std::abs(c.center.x()), std::abs(c.center.y()), std::abs(c.center.z())});
  const auto node = [&](const char* key) { return n[key].IsDefined() ? n[key] : n; };
  if (!(reach <= kMaxReach)) {
    const char* key = std::abs(c.initial_stretch) > kMaxReach / 2 ? "initial_stretch"
                      : std::max(c.size_x, c.size_y) > kMaxReach   ? "size"
                                                                      : "center";
    std::ostringstream msg;
    msg << "the cloth reaches " << reach << " m from the origin, more than " << kMaxReach
        << " m (center, size and initial_stretch together)";
    fail(node(key), path + "." + key, msg.str());
  }
  for (int axis = 0; axis < 2; ++axis) {
    const int count = axis == 0 ? c.nx : c.ny;
    if (count < 2) continue;
    const double spacing = (axis == 0 ? c.size_x : c.size_y) / (count - 1);
    if (!(spacing >= kMinSpacing && spacing >= 1e-9 * reach)) {
      std::ostringstream msg;
      msg << "particles " << spacing << " m apart along axis " << axis << " (size / (particles - 1)), closer than "
          << std::max(kMinSpacing, 1e-9 * reach) << " m: their springs would have no length";
      fail(node("size"), path + ".size", msg.str());
    }
  }
}

ClothDef Reader::cloth(const YAML::Node& n, const std::string& path) const {
  ClothDef c;
  expect_map(n, path, {"particles", "size", "center", "plane", "particle_mass", "springs", "pinned",
                       "initial_stretch", "initial_velocity"});
  optional(n, path, "particles", [&](auto& v, auto& k) {
    if (!v.IsSequence() || v.size() != 2) fail(v, k, "expected [nx, ny], particles along each axis");
    c.nx = int_in_range(v[0], k + "[0]", 1, 2048);
    c.ny = int_in_range(v[1], k + "[1]", 1, 2048);
  });
  optional(n, path, "size", [&](auto& v, auto& k) {
    if (!v.IsSequence() || v.size() != 2) fail(v, k, "expected [width, height] in m");
    c.size_x = positive(v[0], k + "[0]");
    c.size_y = positive(v[1], k + "[1]");
  });
  optional(n, path, "center", [&](auto& v, auto& k) { c.center = vec3(v, k); });
  optional(n, path, "plane", [&](auto& v, auto& k) {
    const std::string p = string(v, k);
    if (p == "xz") c.plane = ClothPlane::XZ;
    else if (p == "xy") c.plane = ClothPlane::XY;
    else fail(v, k, "unknown plane " + in_quotes(p) + " (expected xz or xy)");
  });
  optional(n, path, "particle_mass", [&](auto& v, auto& k) { c.particle_mass = positive(v, k); });
  optional(n, path, "springs", [&](auto& v, auto& k) {
    expect_map(v, k, {"structural", "shear", "bend"});
    c.structural = springs(v["structural"], k + ".structural");
    c.shear = springs(v["shear"], k + ".shear");
    c.bend = springs(v["bend"], k + ".bend");
  });
  optional(n, path, "pinned", [&](auto& v, auto& k) { c.pinned = selection(v, k, c, true); });
  optional(n, path, "initial_stretch", [&](auto& v, auto& k) { c.initial_stretch = number(v, k); });
  optional(n, path, "initial_velocity", [&](auto& v, auto& k) { c.initial_velocity = vec3(v, k); });
  if (c.nx * c.ny < 1) fail(n, path + ".particles", "a cloth needs at least one particle");
  grid_geometry(n, path, c);
  return c;
}

std::optional<SpringParams> Reader::springs(const YAML::Node& n, const std::string& path) const {
  if (!n.IsDefined()) return std::nullopt;  // omitted type: not built
  expect_map(n, path, {"stiffness", "damping"});
  SpringParams p;
  optional(n, path, "stiffness", [&](auto& v, auto& k) { p.stiffness = non_negative(v, k); });
  optional(n, path, "damping", [&](auto& v, auto& k) { p.damping = non_negative(v, k); });
  return p;
}

// The forms of a particle selection (docs/scenes.md, "Pinning"): one item, or a list of
// items, each a named set, a particle [i, j], or a range {i: [i0, i1], j: [j0, j1]}.
std::vector<GridSelection> Reader::selection(const YAML::Node& n, const std::string& key, const ClothDef& c,
                                             bool none_allowed) const {
  if (n.IsScalar() && n.Scalar() == "none") {
    if (!none_allowed) fail(n, key, "'none' selects no particle; leave the key out instead");
    return {};
  }
  if (!n.IsSequence()) return {selection_item(n, key, c)};  // corners, top_edge, {i: ..., j: ...}
  std::vector<GridSelection> out;
  for (std::size_t i = 0; i < n.size(); ++i) out.push_back(selection_item(n[i], key + "." + std::to_string(i), c));
  return out;
}

GridSelection Reader::selection_item(const YAML::Node& n, const std::string& key, const ClothDef& c) const {
  static const char* const kForms =
      "expected corners, top_edge, bottom_edge, left_edge, right_edge, a particle [i, j] or a range "
      "{i: [first, last], j: [first, last]}";
  GridSelection g;
  if (n.IsScalar()) {
    using K = GridSelection::Kind;
    const std::string name = n.Scalar();
    if (name == "corners") g.kind = K::Corners;
    else if (name == "top_edge") g.kind = K::TopEdge;
    else if (name == "bottom_edge") g.kind = K::BottomEdge;
    else if (name == "left_edge") g.kind = K::LeftEdge;
    else if (name == "right_edge") g.kind = K::RightEdge;
    else if (name == "none") fail(n, key, "'none' cannot be listed with other pins");
    else if (!name.empty() && name.find_first_not_of("-0123456789") == std::string::npos)
      fail(n, key, "a number alone is not a particle: write [[i, j]] for one particle, [[i, j], ...] for several");
    else fail(n, key, "unknown selection " + in_quotes(name) + " (" + kForms + ")");
    return g;
  }
  if (n.IsSequence()) {
    if (n.size() != 2) fail(n, key, "expected a particle index [i, j]");
    g.i0 = g.i1 = integer(n[0], key + "[0]");
    g.j0 = g.j1 = integer(n[1], key + "[1]");
    if (g.i0 < 0 || g.i0 >= c.nx || g.j0 < 0 || g.j0 >= c.ny)
      fail(n, key, "particle [" + std::to_string(g.i0) + ", " + std::to_string(g.j0) + "] is outside the " +
                       std::to_string(c.nx) + " x " + std::to_string(c.ny) + " grid");
    return g;
  }
  if (!n.IsMap()) fail(n, key, std::string(kForms) + ", got " + type_name(n));
  expect_map(n, key, {"i", "j"});
  if (n.size() == 0) fail(n, key, "a range needs i (columns), j (rows) or both");
  g.i1 = c.nx - 1;  // a range leaves out an axis to take all of it
  g.j1 = c.ny - 1;
  optional(n, key, "i", [&](auto& v, auto& k) { index_range(v, k, c.nx, g.i0, g.i1); });
  optional(n, key, "j", [&](auto& v, auto& k) { index_range(v, k, c.ny, g.j0, g.j1); });
  return g;
}

// One axis of a range: an index, or [first, last] inclusive, each 0 .. size - 1.
void Reader::index_range(const YAML::Node& n, const std::string& key, int size, int& lo, int& hi) const {
  if (n.IsScalar()) {
    lo = hi = int_in_range(n, key, 0, size - 1);
    return;
  }
  if (!n.IsSequence() || n.size() != 2) fail(n, key, "expected an index or [first, last]");
  lo = int_in_range(n[0], key + "[0]", 0, size - 1);
  hi = int_in_range(n[1], key + "[1]", 0, size - 1);
  if (lo > hi) fail(n, key, "[" + std::to_string(lo) + ", " + std::to_string(hi) + "] runs backwards: expected [first, last]");
}

SphereDef Reader::sphere(const YAML::Node& n, const std::string& path) const {
  SphereDef s;
  expect_map(n, path, {"center", "radius", "kinematic", "mass", "gravity", "restitution",
                       "friction", "velocity", "motion"});
  optional(n, path, "center", [&](auto& v, auto& k) { s.center = vec3(v, k); });
  optional(n, path, "radius", [&](auto& v, auto& k) { s.radius = positive(v, k); });
  optional(n, path, "kinematic", [&](auto& v, auto& k) { s.kinematic = boolean(v, k); });
  optional(n, path, "mass", [&](auto& v, auto& k) {
    s.mass = positive(v, k);
    if (s.kinematic) fail(v, k, "a kinematic sphere has no mass (set kinematic: false for a dynamic one)");
  });
  optional(n, path, "gravity", [&](auto& v, auto& k) { s.gravity = boolean(v, k); });
  optional(n, path, "restitution", [&](auto& v, auto& k) { s.restitution = in_range(v, k, 0, 1); });
  optional(n, path, "friction", [&](auto& v, auto& k) { s.friction = non_negative(v, k); });
  optional(n, path, "velocity", [&](auto& v, auto& k) { s.velocity = vec3(v, k); });
  optional(n, path, "motion", [&](auto& v, auto& k) {
    if (!s.kinematic) fail(v, k, "only a kinematic sphere follows scripted motion");
    if (!v.IsSequence()) fail(v, k, "expected a list of keyframes [{t: s, velocity: [x, y, z]}, ...]");
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string p = k + "." + std::to_string(i);
      expect_map(v[i], p, {"t", "velocity"});
      if (!v[i]["t"].IsDefined() || !v[i]["velocity"].IsDefined())
        fail(v[i], p, "a keyframe needs t and velocity");
      Keyframe kf{non_negative(v[i]["t"], p + ".t"), vec3(v[i]["velocity"], p + ".velocity")};
      if (!s.motion.empty() && kf.t < s.motion.back().t)
        fail(v[i]["t"], p + ".t", "keyframes must be in increasing time");
      s.motion.push_back(kf);
    }
  });
  return s;
}

RenderDef Reader::render(const YAML::Node& n, const std::string& path) const {
  RenderDef r;
  expect_map(n, path, {"width", "height", "fps", "camera", "color", "overlay", "draw_springs", "draw_particles",
                       "samples", "msaa", "antialias"});
  optional(n, path, "width", [&](auto& v, auto& k) { r.width = int_in_range(v, k, RenderDef::kMinSize, RenderDef::kMaxSize); });
  optional(n, path, "height", [&](auto& v, auto& k) { r.height = int_in_range(v, k, RenderDef::kMinSize, RenderDef::kMaxSize); });
  optional(n, path, "fps", [&](auto& v, auto& k) { r.fps = in_range(v, k, 0.0, RenderDef::kMaxFps, true); });
  optional(n, path, "draw_springs", [&](auto& v, auto& k) { r.draw_springs = boolean(v, k); });
  optional(n, path, "draw_particles", [&](auto& v, auto& k) { r.draw_particles = boolean(v, k); });
  optional(n, path, "samples", [&](auto& v, auto& k) {
    r.samples = int_in_range(v, k, 1, 16);
    r.samples_given = true;
  });
  // msaa: 0 (none), 2, 4 or 8 samples; the older `samples` (1 = none) says the same thing.
  optional(n, path, "msaa", [&](auto& v, auto& k) {
    if (n["samples"].IsDefined()) fail(v, k, "give msaa or samples, not both");
    const int m = integer(v, k);
    if (m != 0 && m != 2 && m != 4 && m != 8)
      fail(v, k, "value " + excerpt(v.Scalar()) + " is not one of 0, 2, 4, 8");
    r.samples = m == 0 ? 1 : m;
    r.samples_given = true;
  });
  // antialias: msaa (render.msaa's samples, 4 unless given), fxaa (one sample, edges smoothed
  // on the CPU) or none. A sample count says msaa (more than one sample: samples 2 to 16, msaa
  // 2, 4 or 8) or none (samples 1, msaa 0) by itself: given with antialias, it must say the
  // same, and fxaa takes none. The message says what the key that gave the count allows.
  optional(n, path, "antialias", [&](auto& v, auto& k) {
    const std::string a = string(v, k);
    if (a != "msaa" && a != "fxaa" && a != "none")
      fail(v, k, "unknown antialiasing " + in_quotes(a) + " (expected msaa, fxaa or none)");
    const bool agrees = a == "msaa" ? r.samples > 1 : a == "none" && r.samples == 1;
    if (r.samples_given && !agrees) {
      const bool by_msaa = n["msaa"].IsDefined();
      const std::string count = std::string(by_msaa ? "msaa" : "samples") + ": " + n[by_msaa ? "msaa" : "samples"].Scalar();
      const std::string why = a == "msaa"   ? (by_msaa ? "msaa needs msaa: 2, 4 or 8" : "msaa needs samples: 2 to 16")
                              : a == "none" ? (by_msaa ? "none is msaa: 0" : "none is samples: 1")
                                            : "fxaa draws one sample of its own: leave the count out";
      fail(v, k, a + " contradicts " + count + " (" + why + ")");
    }
    r.antialias = a;
  });
  optional(n, path, "color", [&](auto& v, auto& k) {
    const std::string c = string(v, k);
    if (!parse_field_kind(c)) fail(v, k, "unknown colouring " + in_quotes(c) + " (expected checker, error, strain or speed)");
    r.color = c;
  });
  optional(n, path, "overlay", [&](auto& v, auto& k) {
    const std::string o = string(v, k);
    if (o != "full" && o != "label" && o != "none") fail(v, k, "unknown overlay " + in_quotes(o) + " (expected full, label or none)");
    r.overlay = o;
  });
  optional(n, path, "camera", [&](auto& v, auto& k) {
    // `camera: auto` frames the cloth and spheres from the scene's own extent.
    // `camera: course` is the course framework's view, the defaults of CameraDef.
    if (v.IsScalar()) {
      if (v.Scalar() == "auto") r.camera_auto = true;
      else if (v.Scalar() == "course") r.camera = CameraDef{};
      else fail(v, k, "expected auto, course or a map of eye, target, up, fov, got " + in_quotes(v.Scalar()));
      return;
    }
    expect_map(v, k, {"eye", "target", "up", "fov"});
    optional(v, k, "eye", [&](auto& w, auto& kk) { r.camera.eye = vec3(w, kk); });
    optional(v, k, "target", [&](auto& w, auto& kk) { r.camera.target = vec3(w, kk); });
    optional(v, k, "up", [&](auto& w, auto& kk) { r.camera.up = vec3(w, kk); });
    optional(v, k, "fov", [&](auto& w, auto& kk) { r.camera.fov = in_range(w, kk, 1.0, 170.0); });
    if ((r.camera.eye - r.camera.target).norm() == 0.0) fail(v, k, "eye and target coincide");
  });
  return r;
}

ImplicitDef Reader::implicit(const YAML::Node& n, const std::string& path) const {
  ImplicitDef d;
  expect_map(n, path, {"solver", "newton_max_iterations", "newton_tolerance", "cg_max_iterations",
                       "cg_tolerance", "iterations"});
  optional(n, path, "solver", [&](auto& v, auto& k) {
    const std::string s = string(v, k);
    if (s == "newton") d.solver = ImplicitSolver::Newton;
    else if (s == "fixed_point") d.solver = ImplicitSolver::FixedPoint;
    else fail(v, k, "unknown solver " + in_quotes(s) + " (expected newton or fixed_point)");
  });
  optional(n, path, "newton_max_iterations", [&](auto& v, auto& k) { d.newton_max_iterations = int_in_range(v, k, 1, 1000); });
  optional(n, path, "newton_tolerance", [&](auto& v, auto& k) { d.newton_tolerance = positive(v, k); });
  optional(n, path, "cg_max_iterations", [&](auto& v, auto& k) { d.cg_max_iterations = int_in_range(v, k, 1, 100000); });
  optional(n, path, "cg_tolerance", [&](auto& v, auto& k) { d.cg_tolerance = positive(v, k); });
  optional(n, path, "iterations", [&](auto& v, auto& k) { d.fixed_point_iterations = int_in_range(v, k, 1, 1000); });
  return d;
}

// A list index in a --set key: plain decimal digits only (stoul would also take "+0", " 0"
// and "0x0", so spheres.0x0.radius named sphere 0), at most 9 of them (no overflow).
std::optional<std::size_t> list_index(const std::string& part) {
  if (part.empty() || part.size() > 9) return std::nullopt;
  std::size_t idx = 0;
  for (char c : part) {
    if (c < '0' || c > '9') return std::nullopt;
    idx = idx * 10 + static_cast<std::size_t>(c - '0');
  }
  return idx;
}

// The first YAML document of `text`, and where a second one starts, if any. Not through
// YAML::LoadAll: yaml-cpp 0.7 (Debian 12) loops forever, allocating until the process dies,
// on a stray ',' at the top level (yaml-cpp issue #1040; upstream fixed LoadAll in PR #1319,
// after 0.8.0). Found by the fuzzer (tests/fuzz/regressions/leading_comma*). Here the
// parser's events are only counted, for two documents at most, and a "document" that starts
// where the last one did (the parser made no progress) is not one.
class DocumentStarts : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override { starts.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
  std::vector<YAML::Mark> starts;
};

struct Documents {
  YAML::Node first;
  std::optional<YAML::Mark> second;  // where a second document starts
};

// Throws YAML::Exception as YAML::Load does.
Documents load_documents(const std::string& text) {
  Documents d;
  d.first = YAML::Load(text);
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStarts events;
  for (int k = 0; k < 2 && parser.HandleNextDocument(events); ++k) {
  }
  if (events.starts.size() == 2 && events.starts[1].pos != events.starts[0].pos) d.second = events.starts[1];
  return d;
}

// --set KEY=VALUE: walks the dotted key into the tree (creating map entries, so a key the
// file leaves at its default can be set; list items by index), and puts VALUE, parsed as
// YAML, there. Whether the key exists in the schema is the reader's unknown-key check.
// A list item is never created: an index into a list the scene does not have, or past its
// end, is an error naming the item ("the scene has no spheres[0]"), not a map built where the
// list should be (which the reader would then call "expected a list of spheres, got a map").
void apply_override(YAML::Node& root, const std::string& text, const std::string& file,
                    std::map<std::string, std::string>& applied) {
  const std::string name = "--set " + text;  // cut to an excerpt when the error is formatted
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError(file, 0, name, "expected KEY=VALUE, e.g. cloth.springs.structural.stiffness=1e5");
  const std::string key = text.substr(0, eq), value = text.substr(eq + 1);
  YAML::Node parsed;
  try {
    const Documents documents = load_documents(value);
    if (documents.second) throw SceneError(file, 0, name, "value holds more than one YAML document");
    parsed = documents.first;
  } catch (const YAML::Exception& e) {
    throw SceneError(file, 0, name, "value is not valid YAML: " + excerpt(e.msg));
  }
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) {
    if (part.empty()) throw SceneError(file, 0, name, "empty component in key " + in_quotes(key));
    parts.push_back(part);
  }
  if (key.back() == '.') throw SceneError(file, 0, name, "empty component in key " + in_quotes(key));
  // parts[i] of the key, an index into `list`, the node at parts[0 .. i-1] (nothing there:
  // `list` is undefined or null).
  const auto index_into = [&](const YAML::Node& list, std::size_t i) -> std::size_t {
    const std::string& part = parts[i];
    const std::optional<std::size_t> idx = list_index(part);
    if (!idx) throw SceneError(file, 0, name, in_quotes(part) + " is not an index into a list (plain decimal: 0, 1, 2...)");
    std::string list_key;
    for (std::size_t k = 0; k < i; ++k) list_key += (k ? "." : "") + parts[k];
    const std::string item = "the scene has no " + excerpt(list_key) + "[" + part + "]";
    if (!list.IsSequence())
      throw SceneError(file, 0, name, item + " (it has no " + excerpt(list_key) + ": give the whole list, --set '" +
                                          excerpt(list_key) + "=[...]')");
    if (*idx >= list.size())
      throw SceneError(file, 0, name, item + " (" + excerpt(list_key) + " has " + std::to_string(list.size()) +
                                          (list.size() == 1 ? " item)" : " items)"));
    return *idx;
  };
  // Nothing at the node yet, and a part that can only be an index (no scene key starts with a
  // digit or a sign): a list item that does not exist.
  const auto missing_list_item = [&](const YAML::Node& node, const std::string& part) {
    return (!node.IsDefined() || node.IsNull()) && !part.empty() &&
           (std::isdigit(static_cast<unsigned char>(part[0])) || part[0] == '+' || part[0] == '-');
  };
  YAML::Node cur;
  cur.reset(root);
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    YAML::Node next;
    if (cur.IsSequence() || missing_list_item(cur, p)) {
      next.reset(cur[index_into(cur, i)]);
    } else if (cur.IsMap() || cur.IsNull() || !cur.IsDefined()) {
      next.reset(cur[p]);
    } else {
      throw SceneError(file, 0, name, in_quotes(p) + " is inside a value that is not a map");
    }
    cur.reset(next);
  }
  if (cur.IsSequence() || missing_list_item(cur, parts.back())) {
    cur[index_into(cur, parts.size() - 1)] = parsed;
  } else if (cur.IsScalar()) {
    throw SceneError(file, 0, name, in_quotes(parts.back()) + " is inside a value that is not a map");
  } else {
    cur[parts.back()] = parsed;
  }
  applied[key] = text;
}

// Text sanity before YAML: yaml-cpp's messages for binary junk and tabs are cryptic.
void check_text(const std::string& text, const std::string& file) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw SceneError(file, 0, "", "empty scene file");
  int line = 1;
  bool at_line_start = true;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == 0 || (c < 0x20 && c != '\n' && c != '\r' && c != '\t'))
      throw SceneError(file, line, "", "not a text file (control byte 0x" +
                                           std::string(1, "0123456789abcdef"[c >> 4]) +
                                           std::string(1, "0123456789abcdef"[c & 15]) + ")");
    if (c == '\t' && at_line_start)
      throw SceneError(file, line, "", "tab in indentation: YAML indents with spaces only");
    if (c == '\n') {
      ++line;
      at_line_start = true;
    } else if (c != ' ') {
      at_line_start = false;
    }
  }
}

}  // namespace

SceneDef parse_scene(const std::string& yaml_text, const std::string& source,
                     const std::vector<std::string>& overrides, bool bound_run) {
  check_text(yaml_text, source);
  YAML::Node root;
  try {
    // Every document is read, so that a second one is an error rather than silently ignored
    // (a scene pasted twice, or a stray "---" before more keys).
    const Documents documents = load_documents(yaml_text);
    if (documents.second) {
      const YAML::Mark at = *documents.second;
      throw SceneError(source, at.is_null() ? 0 : at.line + 1, "",
                       "a second YAML document: a scene file holds one (remove the '---' line or the text after it)");
    }
    root = documents.first;
  } catch (const YAML::ParserException& e) {
    throw SceneError(source, e.mark.is_null() ? 0 : e.mark.line + 1, "", "invalid YAML: " + excerpt(e.msg));
  } catch (const YAML::Exception& e) {
    throw SceneError(source, 0, "", "invalid YAML: " + excerpt(e.what()));
  }
  if (!root.IsMap())
    throw SceneError(source, root.Mark().is_null() ? 0 : root.Mark().line + 1, "",
                     std::string("expected a map of scene keys at the top level, got ") + type_name(root));
  std::map<std::string, std::string> applied;
  for (const std::string& o : overrides) apply_override(root, o, source, applied);
  return Reader(source, applied, bound_run).scene(root);
}

SceneDef load_scene(const std::string& path, const std::vector<std::string>& overrides, bool bound_run) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) throw SceneError(path, 0, "", "cannot open: no such file");
  if (S_ISDIR(st.st_mode)) throw SceneError(path, 0, "", "is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, 0, "", "cannot open for reading");
  std::ostringstream buf;
  buf << in.rdbuf();
  return parse_scene(buf.str(), path, overrides, bound_run);
}

}  // namespace clothsim
