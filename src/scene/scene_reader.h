// The scene reader's class, shared by the parser's files: scene_parser.cpp (the top level,
// --set and loading), scene_keys_cloth.cpp (cloth, springs, pinning) and scene_keys_other.cpp
// (spheres, render, solver blocks). Internal to clothsim_scene.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "echo.h"
#include "lane.h"
#include "scene_parser.h"
#include "text.h"

namespace clothsim::scene_detail {

inline std::string join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

inline const char* type_name(const YAML::Node& n) {
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
        std::vector<std::string> names(allowed.begin(), allowed.end());
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        // --set's own aliases (scene/param_keys.h) at the top level, where a --set key starts.
        const bool set_key = path.empty() && overrides_.count(k) > 0;
        if (set_key) names.insert(names.end(), {"ks", "kd"});
        const std::string near = nearest_name(k, names);
        fail(kv.first, join(path, k),
             "unknown key (" + (near.empty() ? "" : "did you mean " + near + "? ") + "expected one of: " + list +
                 (set_key ? "; aliases ks, kd" : "") + ")");
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
  // A mass: > 0 and large enough that its inverse, which the engine works in, is finite.
  double mass(const YAML::Node& n, const std::string& key) const {
    const double m = positive(n, key);
    if (!std::isfinite(1.0 / m)) fail(n, key, "mass " + n.Scalar() + " kg is too small: its inverse is infinite");
    return m;
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
  void apply_scene_lane(const YAML::Node& root, const Lane& lane, SceneDef& s) const;

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
  CollisionDef collision(const YAML::Node& n, const std::string& path, IntegratorKind integrator) const;
  ImplicitDef implicit(const YAML::Node& n, const std::string& path) const;
  void solvers(const YAML::Node& root, SolverDefs& d) const;

  std::string file_;
  std::map<std::string, std::string> overrides_;  // dotted key -> "KEY=VALUE" as typed
  bool bound_run_;  // check duration / dt and the frame count (run_bounds.h)
};

}  // namespace clothsim::scene_detail
