// What the SIMD kernels' tests share: every Highway target forced in turn, and the sheets
// and odd springs they run on.
#pragma once

#include <hwy/targets.h>

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <utility>

#include "core/model/model.h"
#include "core/springs/spring_layout.h"

namespace clothsim::testing {

// Runs check() once with each Highway target this CPU runs and the build compiled forced
// (SCALAR .. AVX3), then gives the choice back to Highway, also when check() returns early
// on a failed ASSERT or throws, so no later test runs on a forced target. Returns the
// targets' names, space-separated, for RecordProperty.
template <class Check>
std::string for_each_highway_target(Check&& check) {
  struct Restore {
    ~Restore() { hwy::SetSupportedTargetsForTest(0); }
  } restore;
  std::string names;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    names += std::string(hwy::TargetName(target)) + " ";
    check(hwy::TargetName(target));
  }
  return names;
}

// A 3 x B field of uniform values in [-1, 1), the same for the same seed.
inline Eigen::Matrix3Xd random_field(int B, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix3Xd m(3, B);
  for (int i = 0; i < B; ++i)
    for (int c = 0; c < 3; ++c) m(c, i) = u(rng);
  return m;
}

// "structural: {}, bend: {}" with each type's own stiffness and damping, so a kernel that
// mixed up families would show it.
inline std::string typed_springs(std::string types) {
  for (const auto& [name, params] : {std::pair{"structural: {}", "structural: {stiffness: 3000, damping: 7}"},
                                     std::pair{"shear: {}", "shear: {stiffness: 2000, damping: 5}"},
                                     std::pair{"bend: {}", "bend: {stiffness: 900, damping: 3}"}})
    if (const auto at = types.find(name); at != std::string::npos) types.replace(at, std::strlen(name), params);
  return types;
}

// One long spring from particle 0 to particle 29, of another stiffness: in no stencil family,
// so the passes run it in their scalar loop. The layout is rebuilt to say so.
inline void add_spring_outside_the_families(Model& m) {
  m.springs.a.push_back(0);
  m.springs.b.push_back(29);
  m.springs.rest.push_back(0.5);
  m.springs.ks.push_back(123.0);
  m.springs.kd.push_back(4.0);
  m.springs.type.push_back(SpringType::Structural);
  m.spring_layout = build_spring_layout(m.springs, m.grid_nx, m.grid_ny);
}

}  // namespace clothsim::testing
