#include "integrator_kind.h"

#include <array>
#include <utility>

namespace clothsim {
namespace {
constexpr std::array<std::pair<IntegratorKind, std::string_view>, 5> kNames{{
    {IntegratorKind::ExplicitEuler, "explicit_euler"},
    {IntegratorKind::SymplecticEuler, "symplectic_euler"},
    {IntegratorKind::Midpoint, "midpoint"},
    {IntegratorKind::Rk4, "rk4"},
    {IntegratorKind::ImplicitEuler, "implicit_euler"},
}};
}  // namespace

std::string_view integrator_name(IntegratorKind kind) {
  for (const auto& [k, name] : kNames)
    if (k == kind) return name;
  return "unknown";
}

std::optional<IntegratorKind> parse_integrator(std::string_view name) {
  for (const auto& [k, n] : kNames)
    if (n == name) return k;
  return std::nullopt;
}

const std::vector<IntegratorKind>& all_integrators() {
  static const std::vector<IntegratorKind> kinds = [] {
    std::vector<IntegratorKind> out;
    for (const auto& entry : kNames) out.push_back(entry.first);
    return out;
  }();
  return kinds;
}

std::string integrator_names_joined() {
  std::string out;
  for (const auto& entry : kNames) {
    if (!out.empty()) out += ", ";
    out += entry.second;
  }
  return out;
}

}  // namespace clothsim
