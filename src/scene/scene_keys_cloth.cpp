// The scene reader's cloth keys: the grid, its springs and particle selections (pinning,
// events). See scene_reader.h.
#include "scene_reader.h"

namespace clothsim::scene_detail {

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
  optional(n, path, "particle_mass", [&](auto& v, auto& k) { c.particle_mass = mass(v, k); });
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

}  // namespace clothsim::scene_detail
