// Test support: reads an MP4 back with libavformat/libavcodec, independently of the
// writer's code, so tests check what a player would see (codec, pixel format, size,
// rate, colour tags, frame count) and the decoded pictures as RGBA.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "render/image.h"

namespace clothsim::test {

struct Mp4Info {
  std::string codec;         // "h264"
  std::string pixel_format;  // "yuv420p"
  int width = 0, height = 0;
  int rate_num = 0, rate_den = 1;  // average frame rate of the video stream
  std::string color_space, color_primaries, color_transfer, color_range;  // "bt709", "tv"
  bool index_first = false;  // moov before mdat (+faststart)
  std::vector<Image> frames; // every decoded picture, in order, converted to RGBA
};

// Throws std::runtime_error when the file cannot be opened or decoded.
Mp4Info probe_mp4(const std::string& path, bool decode_pictures = true);

// Mean RGB of the box of (2r+1)^2 pixels around (x, y), channels 0..255.
std::array<double, 3> mean_rgb(const Image& image, int x, int y, int r);

}  // namespace clothsim::test
