#include "param_keys.h"

#include <cmath>
#include <algorithm>
#include <cstdio>

#include "echo.h"

namespace clothsim {

namespace {

constexpr const char* kSpringGlob = "cloth.springs.*.";

// The one alias table: the course's spring and damper coefficients, over every spring type.
struct Alias {
  const char* name;
  const char* field;
};
constexpr Alias kAliases[] = {{"ks", "stiffness"}, {"kd", "damping"}};

std::string expand_alias(const std::string& key) {
  for (const Alias& a : kAliases)
    if (key == a.name) return std::string(kSpringGlob) + a.field;
  return key;
}

// The spring types the scene builds, in the parser's order.
std::vector<std::string> spring_types(const SceneDef& scene) {
  std::vector<std::string> types;
  if (scene.cloth.structural) types.push_back("structural");
  if (scene.cloth.shear) types.push_back("shear");
  if (scene.cloth.bend) types.push_back("bend");
  return types;
}

// "2e4", "0.5", "750", "1.5e-5": %g, but large and small values by their exponent, in three
// figures; `digits` (3..17) more where two values would otherwise read alike (100, 100.0001).
std::string short_number(double value, int digits) {
  char buf[40];
  const double a = std::abs(value);
  if (a == 0.0 || (a >= 1e-3 && a < 1e4)) {
    std::snprintf(buf, sizeof buf, "%.*g", std::max(6, digits), value);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.*e", digits - 1, value);  // "2.00e+04"
  std::string s = buf;
  const auto e = s.find('e');
  std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
  while (mantissa.back() == '0') mantissa.pop_back();
  if (mantissa.back() == '.') mantissa.pop_back();
  const bool negative = exponent[0] == '-';
  exponent = exponent.substr(1);
  while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

}  // namespace

ParamKey resolve_param_key(const std::string& key, const SceneDef& scene) {
  return ParamKey{key, param_paths(key, spring_types(scene), scene.source)};
}

bool is_param_pattern(const std::string& key) { return expand_alias(key) != key || key.find('*') != std::string::npos; }

std::vector<std::string> param_paths(const std::string& key, const std::vector<std::string>& types,
                                     const std::string& source) {
  if (key.empty()) throw ParamKeyError("the parameter key is empty");
  const std::string path = expand_alias(key);
  if (path.find('*') == std::string::npos) return {path};
  const std::string prefix(kSpringGlob);
  const std::string field = path.substr(std::min(prefix.size(), path.size()));
  if (path.compare(0, prefix.size(), prefix) != 0 || field.empty() || field.find_first_of("*.") != std::string::npos)
    throw ParamKeyError(in_quotes(key) + ": a * stands for a spring type only, as in cloth.springs.*.stiffness");
  std::vector<std::string> paths;
  for (const std::string& type : types) paths.push_back("cloth.springs." + type + "." + field);
  if (paths.empty()) throw ParamKeyError(in_quotes(key) + " matches nothing: " + source + " declares no springs");
  return paths;
}

SceneError as_option_error(const SceneError& e, const ParamKey& key, const std::string& option) {
  for (const std::string& path : key.paths)
    if (e.key.rfind("--set " + path + "=", 0) == 0) return SceneError(e.file, 0, option, e.reason);
  return e;
}

std::vector<std::string> param_sets(const ParamKey& key, double value) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  std::vector<std::string> sets;
  for (const std::string& p : key.paths) sets.push_back(p + "=" + buf);
  return sets;
}

std::string param_label(const ParamKey& key, double value, int digits) {
  return key.label + " = " + short_number(value, std::clamp(digits, 3, 17));
}

}  // namespace clothsim
