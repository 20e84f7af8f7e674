// Image comparison for golden-image tests (ours and users'): `clothsim imgdiff` and
// tests/golden both use this, so what a test accepts is what the command accepts.
#pragma once

#include "image.h"

namespace clothsim {

struct DiffStats {
  double rms = 0.0;            // root-mean-square per-channel difference, 0..255 (RGB only)
  int max = 0;                 // largest per-channel difference, 0..255
  double over_fraction = 0.0;  // share of pixels with any channel differing by more than threshold
};

struct DiffTolerance {
  int pixel_threshold = 16;    // a pixel "differs" when some channel differs by more than this
  double max_rms = 2.0;        // pass if rms <= max_rms ...
  double max_over_fraction = 0.005;  // ... and over_fraction <= this
};

// Images must have the same size (the caller reports a size mismatch itself).
DiffStats compare_images(const Image& a, const Image& b, int pixel_threshold);
bool within_tolerance(const DiffStats& stats, const DiffTolerance& tol);
// A picture of where a and b differ: |a-b| amplified by `gain` over a dimmed copy of a.
Image diff_image(const Image& a, const Image& b, int gain = 8);

}  // namespace clothsim
