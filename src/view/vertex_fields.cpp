#include "vertex_fields.h"

#include <cmath>

namespace clothsim {

std::optional<FieldKind> parse_field_kind(std::string_view name) {
  for (FieldKind k : {FieldKind::None, FieldKind::Error, FieldKind::Strain, FieldKind::Speed})
    if (field_kind_name(k) == name) return k;
  return std::nullopt;
}

std::string_view field_kind_name(FieldKind kind) {
  switch (kind) {
    case FieldKind::None: return "checker";
    case FieldKind::Error: return "error";
    case FieldKind::Strain: return "strain";
    case FieldKind::Speed: return "speed";
  }
  return "checker";
}

std::string field_label(FieldKind kind) {
  switch (kind) {
    case FieldKind::Error: return "error [m]";
    case FieldKind::Strain: return "strain |l/l0-1|";
    case FieldKind::Speed: return "speed [m/s]";
    case FieldKind::None: break;
  }
  return "";
}

std::string field_unit(FieldKind kind) {
  if (kind == FieldKind::Error) return " m";
  if (kind == FieldKind::Speed) return " m/s";
  return "";
}

std::vector<float> vertex_strain(const Model& model, const State& state) {
  const Springs& s = model.springs;
  const int particles = model.num_particles;
  std::vector<double> sum(static_cast<std::size_t>(particles), 0.0);
  std::vector<int> count(static_cast<std::size_t>(particles), 0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double l = (state.x.col(s.a[i]) - state.x.col(s.b[i])).norm();
    const double strain = std::abs(l / s.rest[i] - 1.0);
    for (int p : {s.a[i], s.b[i]}) {
      if (p >= particles) continue;  // springs join particles, but stay safe
      sum[static_cast<std::size_t>(p)] += strain;
      ++count[static_cast<std::size_t>(p)];
    }
  }
  std::vector<float> out(static_cast<std::size_t>(particles), 0.f);
  for (std::size_t p = 0; p < out.size(); ++p)
    if (count[p] > 0) out[p] = static_cast<float>(sum[p] / count[p]);
  return out;
}

std::vector<float> vertex_speed(const Model& model, const State& state) {
  std::vector<float> out(static_cast<std::size_t>(model.num_particles));
  for (int p = 0; p < model.num_particles; ++p) out[static_cast<std::size_t>(p)] = static_cast<float>(state.v.col(p).norm());
  return out;
}

std::vector<float> vertex_distance(const std::vector<double>& x, const std::vector<double>& reference) {
  std::vector<float> out(x.size() / 3, 0.f);
  for (std::size_t p = 0; p < out.size() && 3 * p + 2 < reference.size(); ++p) {
    const double dx = x[3 * p] - reference[3 * p], dy = x[3 * p + 1] - reference[3 * p + 1],
                 dz = x[3 * p + 2] - reference[3 * p + 2];
    out[p] = static_cast<float>(std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return out;
}

}  // namespace clothsim
