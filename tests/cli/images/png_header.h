// A PNG's signature and IHDR alone, claiming w x h pixels: enough for a size read from the
// header, and never decoded (imgdiff and encode judge such sizes before decoding).
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace clothsim::testing {

inline std::string png_header_only(const std::string& path, std::uint32_t w, std::uint32_t h) {
  const unsigned char head[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                static_cast<unsigned char>(w >> 24), static_cast<unsigned char>(w >> 16),
                                static_cast<unsigned char>(w >> 8), static_cast<unsigned char>(w),
                                static_cast<unsigned char>(h >> 24), static_cast<unsigned char>(h >> 16),
                                static_cast<unsigned char>(h >> 8), static_cast<unsigned char>(h), 8, 6, 0, 0, 0};
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(head), sizeof head);
  return path;
}

}  // namespace clothsim::testing
