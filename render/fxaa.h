// FXAA on the CPU: smooths the staircases that a picture rendered with one sample per pixel
// shows along its edges, after Lottes' FXAA 3.11 ("quality" variant, NVIDIA 2011).
//
// Why it is here: llvmpipe shades on the CPU, and its multisampling costs every covered sample,
// so in the comparison clip 4x MSAA was a fifth to a quarter of the whole run's CPU
// (BENCHMARKS.md, "Renderer and PNG"). Finding edges from luma and blending each with its
// neighbour across the edge costs 1.1-1.4 ms of a compare tile's 5.6-5.8 (about 13 000 of its
// 101 000 candidate pixels are edges), against 4-5 ms more for 4x MSAA.
//
// For each pixel the frame drew (or that touches one), where the local luma contrast is above
// a threshold: the edge's orientation from the 3x3 neighbourhood, its two ends searched for
// along it (up to kFxaaReach pixels), and the pixel blended toward its neighbour across the edge
// by how far it lies from the edge's centre (the staircase's step becomes a ramp), or by the
// sub-pixel term where a single pixel stands out. Only the pixel's own colour and one
// neighbour's are mixed, read from the picture as it was: the result does not depend on the
// order of the pixels, and plain float arithmetic keeps it the same on every x86-64.
#pragma once

#include <cstdint>

#include "image.h"

namespace clothsim {

// How far along an edge the search for its ends goes, in pixels: longer edges are treated as
// this long (their ends' pixels get the full ramp, the middle ones none, as MSAA gives nearly
// horizontal lines a shallower ramp).
inline constexpr int kFxaaReach = 24;

// Smooths the edges of `image` in the rectangle [x0, x1) x [y0, y1) (rows top-down), clipped
// to the image. `drawn` (row-major over the rectangle as given, one byte per pixel) is nonzero
// where the frame drew
// over the backdrop; a pixel is considered when it or one of its four neighbours was drawn, so
// the backdrop's own (already smooth) lines are left alone. Null: every pixel is considered.
void fxaa(Image& image, int x0, int y0, int x1, int y1, const std::uint8_t* drawn);

}  // namespace clothsim
