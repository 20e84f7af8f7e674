#include "implicit_cache.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace clothsim {

void ImplicitCacheDeleter::operator()(ImplicitCache* cache) const { delete cache; }

namespace {

// Bitwise equality (a NaN equals itself: the same bits assemble the same matrix).
bool same_bits(const double* a, const double* b, std::size_t n) {
  return n == 0 || std::memcmp(a, b, sizeof(double) * n) == 0;
}

}  // namespace

bool ImplicitCache::holds(const ImplicitSolverState::Linearisation& lin) const {
  return holds_record && lin.h == record.h && lin.damper_h == record.damper_h && lin.drag_h == record.drag_h &&
         lin.y.cols() == record.y.cols() &&
         lin.length.size() == record.length.size() && lin.inv_mass.size() == record.inv_mass.size() &&
         same_bits(lin.y.data(), record.y.data(), static_cast<std::size_t>(lin.y.size())) &&
         same_bits(lin.length.data(), record.length.data(), lin.length.size()) &&
         same_bits(lin.inv_mass.data(), record.inv_mass.data(), static_cast<std::size_t>(lin.inv_mass.size()));
}

ImplicitCache& cache_for(const Model& model, const ImplicitDef& cfg, Workspace& ws) {
  if (!ws.implicit) ws.implicit.reset(new ImplicitCache);
  ImplicitCache& c = *ws.implicit;
  if (c.model == &model && c.single_from == cfg.single_from && c.A.num_bodies() == model.num_bodies() &&
      c.A.num_springs() == model.springs.size())
    return c;
  build_pattern(model, cfg.single_from, c.A);
  c.single_from = cfg.single_from;
  c.damping = SpringBlockMatrix{};  // built for this model when imex first needs it
  c.damping_mark = 0;
  c.y_length.clear();
  c.factor.reset();  // analysed when first needed
  c.multigrid = MultigridPreconditioner{};  // likewise
  c.holds_record = false;
  c.model = &model;
  double sum = 0.0;
  for (std::size_t s = 0; s < model.springs.size(); ++s)
    sum += std::pow(model.springs.ks[s] * model.springs.rest[s], 2);
  c.force_scale = std::sqrt(sum);
  c.shortest_rest = std::numeric_limits<double>::infinity();
  for (double rest : model.springs.rest) c.shortest_rest = std::min(c.shortest_rest, rest);
  c.stiffness = analysis::estimate_stiffness(model);
  return c;
}

}  // namespace clothsim
