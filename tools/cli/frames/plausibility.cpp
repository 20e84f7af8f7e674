#include "plausibility.h"

#include <cstdio>

namespace clothsim::cli {

double cloth_size(const Model& model) {
  if (model.num_particles == 0) return 0.0;
  const Eigen::Matrix3Xd x = model.initial_x.leftCols(model.num_particles);
  return (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).norm();
}

bool external_work(const Model& model) {
  for (int s = 0; s < model.num_spheres; ++s)
    if (model.sphere_kinematic[s] && model.initial_v.col(model.sphere_body(s)).squaredNorm() > 0.0) return true;
  for (const TimedAction& a : model.timeline)
    if (a.kind == TimedAction::Kind::SetVelocity && a.velocity.squaredNorm() > 0.0) return true;
  return false;
}

std::optional<std::string> implausible(const Model& model, const LaneEvidence& e) {
  char text[160];
  const double size = cloth_size(model);
  if (size > 0.0 && e.error_max > kErrorFraction * size) {
    std::snprintf(text, sizeof text, "WRONG: %.2g m from the reference, %.0f%% of the cloth's size", e.error_max,
                  100.0 * e.error_max / size);
    return text;
  }
  const RunTotals& t = e.totals;
  if (t.steps >= kMinSteps && static_cast<double>(t.projected_steps) > kProjectedFraction * static_cast<double>(t.steps) &&
      t.max_strain > kStrainBound) {
    std::snprintf(text, sizeof text, "WRONG: projected on %.0f%% of steps, strain %.2g",
                  100.0 * static_cast<double>(t.projected_steps) / static_cast<double>(t.steps), t.max_strain);
    return text;
  }
  if (!external_work(model) && e.energy_rise > kEnergyRise * model.energy_scale) {
    std::snprintf(text, sizeof text, "WRONG: energy rose %.2g J with no work done on it", e.energy_rise);
    return text;
  }
  return std::nullopt;
}

}  // namespace clothsim::cli
