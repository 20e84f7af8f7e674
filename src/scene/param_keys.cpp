#include "param_keys.h"

#include <cmath>
#include <cstdio>

namespace clothsim {

namespace {

constexpr const char* kSpringGlob = "cloth.springs.*.";

std::string expand_alias(const std::string& key) {
  if (key == "ks") return std::string(kSpringGlob) + "stiffness";
  if (key == "kd") return std::string(kSpringGlob) + "damping";
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

// "2e4", "0.5", "750", "1.5e-5": %g, but large and small values by their exponent, in three figures.
std::string short_number(double value) {
  char buf[32];
  const double a = std::abs(value);
  if (a == 0.0 || (a >= 1e-3 && a < 1e4)) {
    std::snprintf(buf, sizeof buf, "%g", value);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.2e", value);  // "2.00e+04"
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
  if (key.empty()) throw ParamKeyError("the parameter key is empty");
  const std::string path = expand_alias(key);
  ParamKey out{key, {}};
  const auto star = path.find('*');
  if (star == std::string::npos) {
    out.paths.push_back(path);
    return out;
  }
  const std::string prefix(kSpringGlob);
  const std::string field = path.substr(prefix.size());
  if (path.compare(0, prefix.size(), prefix) != 0 || field.empty() || field.find_first_of("*.") != std::string::npos)
    throw ParamKeyError("'" + key + "': a * stands for a spring type only, as in cloth.springs.*.stiffness");
  for (const std::string& type : spring_types(scene)) out.paths.push_back("cloth.springs." + type + "." + field);
  if (out.paths.empty())
    throw ParamKeyError("'" + key + "' matches nothing: " + scene.source + " declares no springs");
  return out;
}

std::vector<std::string> param_sets(const ParamKey& key, double value) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  std::vector<std::string> sets;
  for (const std::string& p : key.paths) sets.push_back(p + "=" + buf);
  return sets;
}

std::string param_label(const ParamKey& key, double value) { return key.label + " = " + short_number(value); }

}  // namespace clothsim
