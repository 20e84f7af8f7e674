// Image: an 8-bit RGBA picture, rows top-down, alpha 255. What the rasterizer produces,
// what PNG files hold and what the video encoder and tile compositor consume.
#pragma once

#include <cstdint>
#include <vector>

namespace clothsim {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // (4 x width x height), row 0 is the top row

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4, 0) {}
  std::uint8_t* pixel(int x, int y) { return &rgba[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const std::uint8_t* pixel(int x, int y) const {
    return &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
  }
  bool empty() const { return width == 0 || height == 0; }
};

}  // namespace clothsim
