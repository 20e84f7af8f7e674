#include "integrator_kind.h"

namespace clothsim {

std::string_view integrator_name(IntegratorKind kind) {
  for (const IntegratorInfo& info : integrator_registry())
    if (info.kind == kind) return info.name;
  return "unknown";
}

std::string method_name(IntegratorKind kind, const ImplicitDef& implicit) {
  if (kind == IntegratorKind::ImplicitEuler && implicit.solver == ImplicitSolver::FixedPoint)
    return std::string(kFixedPointName);
  return std::string(integrator_name(kind));
}

std::optional<IntegratorKind> parse_integrator(std::string_view name) {
  for (const IntegratorInfo& info : integrator_registry())
    if (info.name == name) return info.kind;
  return std::nullopt;
}

const std::vector<IntegratorKind>& all_integrators() {
  static const std::vector<IntegratorKind> kinds = [] {
    std::vector<IntegratorKind> out;
    for (const IntegratorInfo& info : integrator_registry()) out.push_back(info.kind);
    return out;
  }();
  return kinds;
}

std::string integrator_names_joined(std::string_view separator) {
  std::string out;
  for (const IntegratorInfo& info : integrator_registry()) {
    if (!out.empty()) out += separator;
    out += info.name;
  }
  return out;
}

std::vector<IntegratorKind> comparison_integrators() {
  std::vector<IntegratorKind> out;
  for (int slot = 1; slot <= static_cast<int>(integrator_registry().size()); ++slot)
    for (const IntegratorInfo& info : integrator_registry())
      if (info.comparison_slot == slot) out.push_back(info.kind);
  return out;
}

std::string default_comparison_list() {
  std::string out;
  for (IntegratorKind kind : comparison_integrators()) {
    if (!out.empty()) out += ",";
    out += integrator_name(kind);
  }
  return out;
}

}  // namespace clothsim
