#include "plausibility.h"

#include <cstdio>

namespace clothsim::clip {

double cloth_size(const Model& model) {
  if (model.num_particles == 0) return 0.0;
  const Eigen::Matrix3Xd x = model.initial_x.leftCols(model.num_particles);
  return (x.rowwise().maxCoeff() - x.rowwise().minCoeff()).norm();
}

std::optional<std::string> implausible(const Model& model, const LaneEvidence& e) {
  if (e.totals.wrong) return "WRONG: " + e.totals.wrong->reason;
  const double size = cloth_size(model);
  if (size > 0.0 && e.error_max > kErrorFraction * size) {
    char text[160];
    std::snprintf(text, sizeof text, "WRONG: %.2g m from the reference, %.0f%% of the cloth's size", e.error_max,
                  100.0 * e.error_max / size);
    return text;
  }
  return std::nullopt;
}

}  // namespace clothsim::clip
