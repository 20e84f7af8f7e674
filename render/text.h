// A built-in bitmap font drawn on the CPU into an Image, so overlay text is byte-identical
// on every machine (no font files, no hinting drift): golden images stay stable.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "image.h"

namespace clothsim {

using Rgba8 = std::array<std::uint8_t, 4>;

// Glyph cell in pixels at scale 1 (the font covers printable ASCII 32..126).
int text_glyph_width();
int text_glyph_height();
int text_width(std::string_view text, int scale);  // pixels
constexpr int kTextCapHeight = 7;                  // rows of a capital letter at scale 1

// The scale of text over a picture `height` pixels tall (a frame, a tile, a sheet cell): the
// smallest whose cap height is at least height / 30, so 12 px or more at 360 rows and text
// keeps its share of the picture as it grows. 1 up to 210 rows, 2 up to 420, 4 at 720, 6 at 1080.
int text_scale_for_height(int height);

// Draws `text` with its top-left corner at (x, y); `scale` repeats pixels (1, 2, 3...).
// A translucent dark box behind it when `backdrop` is set, so it reads on any background.
// Clipped to the image.
void draw_text(Image& image, int x, int y, std::string_view text, Rgba8 color, int scale,
               bool backdrop = true);

// Darkens the rectangle [x0, x1) x [y0, y1) (clipped) to 35%: the translucent backdrop text
// and legends sit on. Integer arithmetic, identical bytes everywhere.
void darken_rect(Image& image, int x0, int y0, int x1, int y1);

// Lines one below the other (text_glyph_height() * scale apart) on one shared backdrop,
// so the box has no darker bands where per-line boxes would overlap.
void draw_text_block(Image& image, int x, int y, const std::vector<std::string>& lines, Rgba8 color,
                     int scale);

}  // namespace clothsim
