#include "parameter_sweep.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "scene/scene_parser.h"

namespace clothsim::analysis {
namespace {

// The node at dotted `param` in the scene file (list items by index), if the file has it.
std::optional<YAML::Node> find_node(const std::string& path, const std::string& param) {
  try {
    YAML::Node node = YAML::LoadFile(path);
    std::stringstream parts(param);
    for (std::string part; std::getline(parts, part, '.');) {
      if (node.IsSequence()) {
        const std::size_t index = std::stoul(part);
        if (index >= node.size()) return std::nullopt;
        node.reset(node[index]);
      } else if (node.IsMap()) {
        const YAML::Node next = node[part];
        if (!next.IsDefined()) return std::nullopt;
        node.reset(next);
      } else {
        return std::nullopt;
      }
    }
    return node;
  } catch (const std::exception&) {  // YAML errors, stoul on a non-index: no such node
    return std::nullopt;
  }
}

}  // namespace

std::string set_text(const std::string& param, double value) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  return param + "=" + buf;
}

std::vector<SweepScene> sweep_scenes(const std::string& path, const std::vector<std::string>& sets,
                                     const std::string& param, const std::vector<double>& values) {
  return sweep_scenes(path, sets, std::vector<std::string>{param}, values);
}

std::vector<SweepScene> sweep_scenes(const std::string& path, const std::vector<std::string>& sets,
                                     const std::vector<std::string>& params, const std::vector<double>& values) {
  const std::string param = params.empty() ? std::string() : params.front();  // checked as the others
  if (param.empty()) throw StudyError("the swept parameter is empty");
  if (values.empty()) throw StudyError("no values given (an empty list)");
  for (double v : values)
    if (!std::isfinite(v)) throw StudyError("value " + std::to_string(v) + " is not a finite number");

  std::vector<std::string> probe = sets;
  probe.push_back(param + "=not-a-number");
  bool accepts_text = true;
  try {
    load_scene(path, probe);
  } catch (const SceneError&) {
    accepts_text = false;  // good: a numeric key rejects a word (or the key does not exist: see below)
  }
  if (accepts_text) throw StudyError(param + " is not a numeric scene key (it accepts text)");

  std::vector<SweepScene> out;
  for (double v : values) {
    std::vector<std::string> with = sets;
    for (const std::string& p : params) with.push_back(set_text(p, v));
    try {
      out.push_back({v, load_scene(path, with)});
    } catch (const SceneError&) {
      // A key the file gives as a word or a list (cloth.plane: xz, gravity: [...]) is not a
      // number to sweep: say so rather than pass on the parser's complaint about the value.
      const std::optional<YAML::Node> node = find_node(path, param);
      if (node && (!node->IsScalar() || !parameter_value(path, {}, param)))
        throw StudyError(param + " is not a numeric scene key (the scene gives it " +
                         (node->IsScalar() ? "'" + node->Scalar() + "'" : std::string("a list or map")) + ")");
      throw;  // unknown key, out of range, ...: the parser's message names it
    }
  }
  return out;
}

std::optional<double> parameter_value(const std::string& path, const std::vector<std::string>& sets,
                                      const std::string& param) {
  // The last --set of the key wins, as in the parser.
  for (auto it = sets.rbegin(); it != sets.rend(); ++it)
    if (it->rfind(param + "=", 0) == 0) {
      try {
        return YAML::Load(it->substr(param.size() + 1)).as<double>();
      } catch (const YAML::Exception&) {
        return std::nullopt;
      }
    }
  const std::optional<YAML::Node> node = find_node(path, param);
  if (!node || !node->IsScalar()) return std::nullopt;
  try {
    return node->as<double>();
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

}  // namespace clothsim::analysis
