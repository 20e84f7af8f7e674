#include "golden_manifest.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "scene/names.h"
#include "scene/scene_parser.h"
#include "clip/common/cli_common.h"
#include "core/integrators/integrator_kind.h"

namespace clothsim::clip {

namespace fs = std::filesystem;

namespace {

// Reads the YAML tree, every error one SceneError naming the manifest, the line and the key.
class ManifestReader {
 public:
  explicit ManifestReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    const int line = node.IsDefined() && !node.Mark().is_null() ? node.Mark().line + 1 : 0;
    throw SceneError(file_, line, key, what);
  }

  void expect_keys(const YAML::Node& node, const std::string& path, const std::set<std::string>& allowed) const {
    if (!node.IsMap()) fail(node, path, "expected a map");
    std::set<std::string> seen;
    for (const auto& kv : node) {
      const std::string k = kv.first.Scalar();
      const std::string key = path.empty() ? k : path + "." + k;
      if (!allowed.count(k)) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(kv.first, key, "unknown key (expected one of: " + list + ")");
      }
      if (!seen.insert(k).second) fail(kv.first, key, "duplicate key");
    }
  }

  double number(const YAML::Node& n, const std::string& key, double lo, bool lo_open) const {
    double v = NAN;
    if (n.IsScalar()) {
      try {
        v = n.as<double>();
      } catch (const YAML::Exception&) {
        // Every time syntax the commands take (--dt 1/60, a scene's dt: 1/60): a fraction too.
        if (const std::optional<double> f = parse_number_or_fraction(n.Scalar())) v = *f;
      }
    }
    if (!std::isfinite(v))
      fail(n, key, "expected a number (or a fraction like 1/60), got '" + (n.IsScalar() ? n.Scalar() : "a list or map") + "'");
    if (lo_open ? !(v > lo) : !(v >= lo)) {
      std::ostringstream msg;
      msg << "value " << n.Scalar() << " out of range: must be " << (lo_open ? "> " : ">= ") << lo;
      fail(n, key, msg.str());
    }
    return v;
  }

  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar() || n.Scalar().empty()) fail(n, key, "expected a non-empty string");
    return n.Scalar();
  }

  void size(const YAML::Node& n, const std::string& key, int& width, int& height) const {
    if (!n.IsSequence() || n.size() != 2) fail(n, key, "expected [width, height] in pixels");
    const double w = number(n[0], key + "[0]", 0, true), h = number(n[1], key + "[1]", 0, true);
    if (w != std::floor(w) || h != std::floor(h) || w > 16384 || h > 16384)
      fail(n, key, "expected whole pixels from 1 to 16384");
    width = static_cast<int>(w);
    height = static_cast<int>(h);
  }

  void tolerance(const YAML::Node& n, const std::string& key, DiffTolerance& t) const {
    expect_keys(n, key, {"threshold", "max_rms", "max_over"});
    if (n["threshold"]) {
      const double v = number(n["threshold"], key + ".threshold", 0, false);
      if (v != std::floor(v) || v > 255) fail(n["threshold"], key + ".threshold", "expected a whole number from 0 to 255");
      t.pixel_threshold = static_cast<int>(v);
    }
    if (n["max_rms"]) t.max_rms = number(n["max_rms"], key + ".max_rms", 0, false);
    if (n["max_over"]) {
      t.max_over_fraction = number(n["max_over"], key + ".max_over", 0, false);
      if (t.max_over_fraction > 1) fail(n["max_over"], key + ".max_over", "a fraction of the pixels: from 0 to 1");
    }
  }

  GoldenEntry entry(const YAML::Node& n, const std::string& key, const GoldenEntry& defaults,
                    const fs::path& dir) const {
    expect_keys(n, key, {"scene", "name", "kind", "integrator", "integrators", "dt", "times", "size", "tolerance"});
    GoldenEntry e = defaults;
    e.line = n.Mark().is_null() ? 0 : n.Mark().line + 1;
    if (n["kind"]) {
      const std::string kind = text(n["kind"], key + ".kind");
      if (kind != "still" && kind != "compare") fail(n["kind"], key + ".kind", "expected still or compare, got '" + kind + "'");
      e.compare = kind == "compare";
    }
    if (e.compare && n["integrator"])
      fail(n["integrator"], key + ".integrator", "a compare entry runs its lanes: give them as integrators: [rk4, midpoint]");
    if (!e.compare && n["integrators"])
      fail(n["integrators"], key + ".integrators", "only a kind: compare entry has lanes (a still runs one: integrator:)");
    if (const YAML::Node lanes = n["integrators"]) {
      if (lanes.IsSequence()) {
        if (lanes.size() == 0) fail(lanes, key + ".integrators", "expected at least one lane");
        for (std::size_t i = 0; i < lanes.size(); ++i)
          e.integrators += (i ? "," : "") + text(lanes[i], key + ".integrators[" + std::to_string(i) + "]");
      } else {
        e.integrators = text(lanes, key + ".integrators");
      }
    }
    if (!n["scene"]) fail(n, key + ".scene", "missing: the scene file, relative to the manifest");
    const std::string scene = text(n["scene"], key + ".scene");
    e.scene = fs::path(scene).is_absolute() ? scene : (dir / scene).lexically_normal().string();
    e.name = n["name"] ? text(n["name"], key + ".name") : fs::path(scene).stem().string();
    // The name becomes NAME_tXms.png beside the manifest: a NUL or '/' would write elsewhere.
    if (const std::string problem = name_problem(e.name); !problem.empty())
      n["name"] ? fail(n["name"], key + ".name", problem) : fail(n["scene"], key + ".scene", "its file stem " + problem);
    if (n["integrator"]) {
      e.integrator = parse_integrator(text(n["integrator"], key + ".integrator"));
      if (!e.integrator)
        fail(n["integrator"], key + ".integrator",
             "unknown integrator '" + n["integrator"].Scalar() + "' (expected one of: " + integrator_names_joined() + ")");
    }
    // The line of a key's value, for what is judged later against the scene (golden_check.cpp).
    const auto line_of = [&](const YAML::Node& v) { return v.Mark().is_null() ? e.line : v.Mark().line + 1; };
    if (n["dt"]) {
      e.dt = number(n["dt"], key + ".dt", 0, true);
      e.dt_line = line_of(n["dt"]);
    }
    const YAML::Node times = n["times"];
    if (!times) fail(n, key + ".times", "missing: the times (s) to render, e.g. [1.0]");
    if (!times.IsSequence() || times.size() == 0) fail(times, key + ".times", "expected a non-empty list of times (s)");
    e.times_line = line_of(times);
    for (std::size_t i = 0; i < times.size(); ++i)
      e.times.push_back(number(times[i], key + ".times[" + std::to_string(i) + "]", 0, false));
    if (!std::is_sorted(e.times.begin(), e.times.end()) ||
        std::adjacent_find(e.times.begin(), e.times.end()) != e.times.end())
      fail(times, key + ".times", "expected increasing times");
    if (n["size"]) size(n["size"], key + ".size", e.width, e.height);
    if (n["tolerance"]) tolerance(n["tolerance"], key + ".tolerance", e.tolerance);
    return e;
  }

 private:
  std::string file_;
};

// Milliseconds in the file name: whole ones as the project's goldens have them (1500ms),
// finer times with the digits they need (0.25ms).
std::string time_tag(double t) {
  std::ostringstream s;
  s.precision(12);
  s << t * 1000.0;
  return s.str();
}

}  // namespace

GoldenManifest load_golden_manifest(const std::string& path) {
  if (!fs::is_regular_file(path)) throw SceneError(path, 0, "", "cannot open: no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, 0, "", "cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  YAML::Node root;
  try {
    // Every document is parsed, so a broken second one is an error, not silently skipped.
    const std::vector<YAML::Node> documents = YAML::LoadAll(text.str());
    if (documents.size() > 1)
      throw SceneError(path, documents[1].Mark().is_null() ? 0 : documents[1].Mark().line + 1, "",
                       "a second YAML document: a manifest is one document (remove the '---' and what follows)");
    if (!documents.empty()) root = documents.front();
  } catch (const YAML::ParserException& e) {
    throw SceneError(path, yaml_error_line(text.str(), e), "", "invalid YAML: " + e.msg);
  }
  const ManifestReader r(path);
  if (!root.IsMap()) r.fail(root, "", "expected a map with a 'goldens' list");
  r.expect_keys(root, "", {"goldens", "size", "tolerance"});
  GoldenEntry defaults;
  if (root["size"]) r.size(root["size"], "size", defaults.width, defaults.height);
  if (root["tolerance"]) r.tolerance(root["tolerance"], "tolerance", defaults.tolerance);
  const YAML::Node goldens = root["goldens"];
  if (!goldens) r.fail(root, "goldens", "missing: the list of scenes to render");
  if (!goldens.IsSequence() || goldens.size() == 0) r.fail(goldens, "goldens", "expected a non-empty list");

  GoldenManifest manifest;
  manifest.path = path;
  const fs::path dir = fs::path(path).parent_path();
  std::map<std::string, std::string> images;  // image file -> the key that writes it
  for (std::size_t i = 0; i < goldens.size(); ++i) {
    const std::string key = "goldens[" + std::to_string(i) + "]";
    manifest.entries.push_back(r.entry(goldens[i], key, defaults, dir));
    for (double t : manifest.entries.back().times) {
      const std::string image = golden_image_path(manifest, manifest.entries.back(), t);
      const auto [it, fresh] = images.emplace(image, key);
      if (!fresh)
        r.fail(goldens[i], key + ".name", "writes " + fs::path(image).filename().string() + " as " + it->second +
                                              " does: give one of them another name");
    }
  }
  return manifest;
}

std::string golden_image_path(const GoldenManifest& manifest, const GoldenEntry& entry, double t) {
  return (fs::path(manifest.path).parent_path() / (entry.name + "_t" + time_tag(t) + "ms.png")).string();
}

}  // namespace clothsim::clip
