// The model's springs as a structure of arrays (the force pass streams through them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace clothsim {

enum class SpringType : std::uint8_t { Structural = 0, Shear = 1, Bend = 2 };

// Springs as a structure of arrays (S springs).
struct Springs {
  std::vector<std::int32_t> a, b;  // (S) particle indices, a < b
  std::vector<double> rest;        // (S) rest length l0, m
  std::vector<double> ks, kd;      // (S) stiffness N/m, damping N s/m
  std::vector<SpringType> type;    // (S)
  std::size_t size() const { return a.size(); }
};

}  // namespace clothsim
