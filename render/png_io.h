// PNG files through libpng: fast zlib settings for frame sequences, tEXt metadata.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "image.h"
#include "io/output_file.h"  // Replace

namespace clothsim {

struct PngError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

using PngText = std::vector<std::pair<std::string, std::string>>;  // tEXt key/value chunks

// Writes through an OutputFile (named only when complete), so a failed write leaves nothing.
// Throws PngError "cannot write PATH: reason" (the system's errno text for I/O errors).
// `replace`: how an existing file goes (output_file.h; a frame sequence removes it first).
void write_png(const std::string& path, const Image& image, const PngText& text = {},
               int zlib_level = 2, Replace replace = Replace::kAtomic);
// Reads any 8-bit PNG (grey, RGB, RGBA, palette) as RGBA. Throws PngError (missing, corrupt).
Image read_png(const std::string& path, PngText* text = nullptr);

// A PNG's width and height from its header alone, so a size can be judged before decoding.
// Throws PngError (missing, not a PNG, no IHDR first).
struct PngSize {
  int width = 0, height = 0;
};
PngSize read_png_size(const std::string& path);

}  // namespace clothsim
