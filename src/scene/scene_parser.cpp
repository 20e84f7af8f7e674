// The scene parser: text -> YAML tree (+ --set overrides) -> SceneDef, validating as it
// reads. Every field is read by one typed accessor that knows its dotted key and its node's
// line, so every error can say where it is; every map is checked for keys it does not know.
#include "scene_parser.h"
#include "scene_reader.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "echo.h"
#include "lane.h"
#include "names.h"
#include "param_keys.h"
#include "run_bounds.h"
#include "core/integrators/integrator_kind.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
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
      key(std::move(key_)),
      reason(what) {}

namespace scene_detail {

// A lane's step and settings, said once: `integrator: rk4@2e-4` beside `dt:`, or `vbd:10` beside
// a `vbd:` block, would say one thing twice, perhaps two ways, so either is refused.
void Reader::apply_scene_lane(const YAML::Node& root, const Lane& lane, SceneDef& s) const {
  const YAML::Node key = root["integrator"];
  if (lane.written_step() && root["dt"].IsDefined())
    fail(key, "integrator", in_quotes(key.Scalar()) + " gives the step, and so does dt (line " +
                                std::to_string(root["dt"].Mark().line + 1) + "): give it in one place");
  const bool settings = lane.fixed_point || lane.iterations > 0 || lane.tolerance > 0.0;
  const std::string block = lane.kind == kBackwardEuler ? "implicit" : std::string(integrator_name(lane.kind));
  if (settings && root[block].IsDefined())
    fail(key, "integrator", in_quotes(key.Scalar()) + " sets " + block + "'s solver, and so does the " + block +
                                ": block (line " + std::to_string(root[block].Mark().line + 1) + "): give it in one place");
  apply_lane(s, lane);
}

SceneDef Reader::scene(const YAML::Node& root) const {
  SceneDef s;
  s.source = file_;
  expect_map(root, "", {"name", "duration", "dt", "integrator", "gravity", "air_drag", "cloth",
                        "spheres", "ground", "collision", "events", "render", "implicit",
                        "divergence", "xpbd", "projective_dynamics", "vbd"});
  optional(root, "", "name", [&](auto& n, auto& k) {
    s.name = string(n, k);
    if (const std::string problem = name_problem(s.name); !problem.empty()) fail(n, k, problem);  // names.h
  });
  optional(root, "", "duration", [&](auto& n, auto& k) { s.duration = non_negative(n, k); });
  optional(root, "", "dt", [&](auto& n, auto& k) { s.dt = positive(n, k); });
  // The lane grammar (lane.h): `integrator: xpbd@1/60:5` is a lane, its settings written into
  // the scene once every block is read.
  std::optional<Lane> lane;
  optional(root, "", "integrator", [&](auto& n, auto& k) {
    try {
      lane = parse_lane(string(n, k));
    } catch (const LaneError& e) {
      fail(n, k, e.what());
    }
    s.integrator = lane->kind;
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
  optional(root, "", "collision", [&](auto& n, auto& k) { s.collision = collision(n, k, s.integrator); });
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
  solvers(root, s.solvers);
  if (lane) apply_scene_lane(root, *lane, s);
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

}  // namespace scene_detail

namespace {
using scene_detail::Reader;
using scene_detail::type_name;

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

// The spring types the file declares under cloth.springs, in the parser's order: what a
// glob or an alias in --set (ks, cloth.springs.*.damping) stands for.
std::vector<std::string> declared_spring_types(const YAML::Node& root) {
  std::vector<std::string> types;
  // (a key absent under a const node is an invalid node, defined or not, so IsDefined first)
  const YAML::Node cloth = root["cloth"];
  if (!cloth.IsDefined() || !cloth.IsMap()) return types;
  const YAML::Node springs = cloth["springs"];
  if (!springs.IsDefined() || !springs.IsMap()) return types;
  for (const char* type : {"structural", "shear", "bend"}) {
    const YAML::Node n = springs[type];
    if (n.IsDefined() && !n.IsNull()) types.emplace_back(type);
  }
  return types;
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

int yaml_error_line(const std::string& text, const YAML::ParserException& e) {
  if (e.mark.is_null()) return 0;
  // "end of sequence flow not found": yaml-cpp's mark is where it stopped, a line past the '['.
  if (e.msg.find("flow not found") != std::string::npos)
    if (const int opened = unclosed_bracket_line(text, static_cast<std::size_t>(std::max(e.mark.pos, 0))); opened > 0)
      return opened;
  return e.mark.line + 1;
}

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
    throw SceneError(source, yaml_error_line(yaml_text, e), "", "invalid YAML: " + excerpt(e.msg));
  } catch (const YAML::Exception& e) {
    throw SceneError(source, 0, "", "invalid YAML: " + excerpt(e.what()));
  }
  if (!root.IsMap())
    throw SceneError(source, root.Mark().is_null() ? 0 : root.Mark().line + 1, "",
                     std::string("expected a map of scene keys at the top level, got ") + type_name(root));
  std::map<std::string, std::string> applied;
  for (const std::string& o : overrides) {
    const std::string key = o.substr(0, o.find('='));
    if (!is_param_pattern(key) || o.find('=') == std::string::npos) {
      apply_override(root, o, source, applied);
      continue;
    }
    std::vector<std::string> paths;
    try {
      paths = param_paths(key, declared_spring_types(root), source);
    } catch (const ParamKeyError& e) {
      throw SceneError(source, 0, "--set " + o, e.what());
    }
    for (const std::string& path : paths) {  // each value's error names what was typed
      apply_override(root, path + o.substr(key.size()), source, applied);
      applied[path] = o;
    }
  }
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