// libpng reports errors by longjmp from its error callback; each libpng call sequence below
// sits in a function whose only locals with destructors live outside the setjmp frame, and
// the error text is carried out in a plain buffer, then thrown as PngError with the path.
// Bytes go out through our own write callback, so a failed write (a full disk, a file-size
// limit) says the system's reason, not libpng's bare "Write Error"; the file is an
// OutputFile, named only when complete.
#include "png_io.h"

#include <png.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>

#include "io/output_file.h"

namespace clothsim {

namespace {

struct ErrorSink {
  std::jmp_buf jump;
  char message[256] = "";
  std::FILE* file = nullptr;  // writing: where the bytes go
};

void on_error(png_structp png, png_const_charp message) {
  auto* sink = static_cast<ErrorSink*>(png_get_error_ptr(png));
  std::snprintf(sink->message, sizeof sink->message, "%s", message);
  std::longjmp(sink->jump, 1);
}
void on_warning(png_structp, png_const_charp) {}  // e.g. a bad CRC in an ancillary chunk: keep going

// libpng's write callbacks: stdio on the OutputFile's stream, errno's text on failure.
void write_bytes(png_structp png, png_bytep data, png_size_t size) {
  auto* sink = static_cast<ErrorSink*>(png_get_error_ptr(png));
  if (std::fwrite(data, 1, size, sink->file) != size) png_error(png, std::strerror(errno));
}
void flush_bytes(png_structp png) {
  auto* sink = static_cast<ErrorSink*>(png_get_error_ptr(png));
  if (std::fflush(sink->file) != 0) png_error(png, std::strerror(errno));
}

std::string reason() { return std::strerror(errno); }

// The libpng part of writing; returns false with sink->message set on a libpng error.
bool encode(std::FILE* file, const Image& image, int zlib_level, std::vector<png_text>& chunks,
            std::vector<std::uint8_t>& rgb, ErrorSink* sink) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, on_error, on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(sink->message, sizeof sink->message, "out of memory");
    return false;
  }
  if (setjmp(sink->jump)) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  sink->file = file;
  png_set_write_fn(png, nullptr, write_bytes, flush_bytes);
  png_set_compression_level(png, zlib_level);
  // No row filter: rendered frames are flat fields and smooth gradients whose repeats deflate's
  // LZ matching finds unfiltered. Measured on a 1280x720 drape frame at level 1: 13 ms and
  // 198 kB, where libpng's adaptive filtering takes 24 ms for 222 kB and up + Z_RLE 23 ms for 408 kB.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  // RGB, not RGBA: the frames are opaque, and a quarter fewer bytes to filter and deflate.
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  if (!chunks.empty()) png_set_text(png, info, chunks.data(), static_cast<int>(chunks.size()));
  png_write_info(png, info);
  const std::size_t width = static_cast<std::size_t>(image.width);
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* src = image.pixel(0, y);
    for (std::size_t x = 0; x < width; ++x) std::copy(src + 4 * x, src + 4 * x + 3, &rgb[3 * x]);
    png_write_row(png, rgb.data());
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void write_png(const std::string& path, const Image& image, const PngText& text, int zlib_level,
               Replace replace) {
  if (image.empty()) throw PngError("cannot write " + path + ": the image is empty");
  if (image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4)
    throw PngError("cannot write " + path + ": the image's pixel buffer does not match its size");
  std::vector<png_text> chunks;
  for (const auto& [key, value] : text) {
    // tEXt keys: 1 to 79 printable Latin-1 characters (PNG spec 11.3.4.3).
    if (key.empty() || key.size() > 79) throw PngError("cannot write " + path + ": tEXt key \"" + key + "\" must be 1 to 79 characters");
    png_text chunk{};
    chunk.compression = PNG_TEXT_COMPRESSION_NONE;
    chunk.key = const_cast<char*>(key.c_str());
    chunk.text = const_cast<char*>(value.c_str());
    chunk.text_length = value.size();
    chunks.push_back(chunk);
  }

  std::optional<OutputFile> file;
  try {
    file.emplace(path, replace);
  } catch (const OutputFileError& e) {
    throw PngError(e.what());
  }
  auto sink = std::make_unique<ErrorSink>();
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(image.width) * 3);  // one row, alpha dropped
  if (!encode(file->stream(), image, std::clamp(zlib_level, 0, 9), chunks, rgb, sink.get()))
    throw PngError("cannot write " + path + ": " + sink->message);  // file dropped unnamed
  try {
    file->commit();  // a full disk can surface only here
  } catch (const OutputFileError& e) {
    throw PngError(e.what());
  }
}

namespace {

// The libpng part of reading into `image` (RGBA 8-bit); false with sink->message on error.
bool decode(std::FILE* file, Image& image, PngText* text, ErrorSink* sink, std::vector<png_bytep>& rows) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, sink, on_error, on_warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    std::snprintf(sink->message, sizeof sink->message, "out of memory");
    return false;
  }
  if (setjmp(sink->jump)) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_init_io(png, file);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  // Normalise every PNG flavour to 8-bit RGBA: palettes and low-bit grey expanded,
  // 16-bit reduced, grey copied to RGB, opaque alpha added where there is none.
  png_set_expand(png);
  png_set_strip_16(png);
  png_set_gray_to_rgb(png);
  png_set_add_alpha(png, 0xFF, PNG_FILLER_AFTER);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  if (png_get_rowbytes(png, info) != static_cast<std::size_t>(width) * 4) png_error(png, "unsupported pixel layout");
  if (width > 65535 || height > 65535) png_error(png, "image larger than 65535 pixels per side");
  image = Image(static_cast<int>(width), static_cast<int>(height));
  rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = image.pixel(0, static_cast<int>(y));
  png_read_image(png, rows.data());
  png_read_end(png, info);
  if (text) {
    png_textp chunks = nullptr;
    int count = 0;
    png_get_text(png, info, &chunks, &count);
    for (int i = 0; i < count; ++i)
      text->emplace_back(chunks[i].key, std::string(chunks[i].text, chunks[i].text_length));
  }
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

}  // namespace

PngSize read_png_size(const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file) throw PngError("cannot read " + path + ": " + reason());
  png_byte head[24] = {};  // signature, then the IHDR chunk's length, type, width and height
  if (std::fread(head, 1, sizeof head, file.get()) != sizeof head || png_sig_cmp(head, 0, 8) != 0)
    throw PngError("cannot read " + path + ": not a PNG file");
  if (std::memcmp(head + 12, "IHDR", 4) != 0) throw PngError("cannot read " + path + ": corrupt PNG (no IHDR first)");
  const auto be32 = [&](int at) {
    return (std::uint32_t(head[at]) << 24) | (std::uint32_t(head[at + 1]) << 16) | (std::uint32_t(head[at + 2]) << 8) |
           std::uint32_t(head[at + 3]);
  };
  const std::uint32_t w = be32(16), h = be32(20);
  if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu)
    throw PngError("cannot read " + path + ": corrupt PNG (size " + std::to_string(w) + "x" + std::to_string(h) + ")");
  return {static_cast<int>(w), static_cast<int>(h)};
}

Image read_png(const std::string& path, PngText* text) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file) throw PngError("cannot read " + path + ": " + reason());
  png_byte signature[8] = {};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    throw PngError("cannot read " + path + ": not a PNG file");
  Image image;
  PngText chunks;
  auto sink = std::make_unique<ErrorSink>();
  std::vector<png_bytep> rows;
  if (!decode(file.get(), image, text ? &chunks : nullptr, sink.get(), rows))
    throw PngError("cannot read " + path + ": corrupt PNG (" + sink->message + ")");
  if (text) *text = std::move(chunks);
  return image;
}

}  // namespace clothsim
