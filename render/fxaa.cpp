#include "fxaa.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace clothsim {

namespace {

// FXAA 3.11's thresholds: a pixel is an edge where its cross's luma range is at least 1/8 of
// its brightest ("high quality") and at least 1/32 of full scale ("visible limit"; dark noise
// below it is left alone)
// (is_edge); the sub-pixel term at 3/4 strength.
constexpr float kSubpixel = 0.75f;
// The search steps along the edge, in pixels (they add up to kFxaaReach): fine near the pixel,
// where most ends are, coarser further out.
constexpr int kSteps[] = {1, 1, 1, 1, 1, 2, 2, 3, 4, 8};

constexpr int sum_of_steps() {
  int s = 0;
  for (int step : kSteps) s += step;
  return s;
}
static_assert(sum_of_steps() == kFxaaReach, "kFxaaReach is how far the search steps reach");

// Luma of display values, 0..255 (BT.709 weights in 1/256ths): what the eye sees as an edge.
// Integers, so the edge test is exact and the same everywhere.
std::uint8_t luma_of(const std::uint8_t* p) {
  return static_cast<std::uint8_t>((54 * p[0] + 183 * p[1] + 19 * p[2] + 128) >> 8);
}

// The luma of the rectangle and `pad` pixels around it, the image's border rows and columns
// repeated past its edges, so every read is a plain index.
class LumaPlane {
 public:
  LumaPlane(const Image& image, int x0, int y0, int x1, int y1, int pad)
      : x0_(x0 - pad), y0_(y0 - pad), stride_(x1 - x0 + 2 * pad),
        values_(static_cast<std::size_t>(stride_) * (y1 - y0 + 2 * pad)) {
    const int rows = y1 - y0 + 2 * pad;
    const int xs = std::max(x0_, 0), xe = std::min(x0_ + stride_, image.width);  // inside the image
    for (int r = 0; r < rows; ++r) {
      const int y = std::clamp(y0_ + r, 0, image.height - 1);
      std::uint8_t* out = &values_[static_cast<std::size_t>(r) * stride_];
      const std::uint8_t* p = image.pixel(0, y);
      for (int x = xs; x < xe; ++x) out[x - x0_] = luma_of(p + 4 * x);
      std::fill(out, out + (xs - x0_), out[xs - x0_]);                        // left of the image
      std::fill(out + (xe - x0_), out + stride_, out[xe - 1 - x0_]);           // right of it
    }
  }
  int stride() const { return stride_; }
  const std::uint8_t* at(int x, int y) const {
    return &values_[static_cast<std::size_t>(y - y0_) * stride_ + (x - x0_)];
  }

 private:
  int x0_, y0_, stride_;
  std::vector<std::uint8_t> values_;
};

struct Blend {
  int x, y;            // the pixel
  int nx, ny;          // its neighbour across the edge
  float amount;        // 0..1: how much of the neighbour's colour
};

// Whether the pixel's cross has the contrast of an edge: its luma range at least 1/8 of its
// brightest and at least 8 of 255 (kEdgeThreshold, kEdgeThresholdMin in integers).
bool is_edge(const std::uint8_t* c, int stride) {
  const int m = c[0], n = c[-stride], s = c[stride], w = c[-1], e = c[1];
  // (pairwise: std::max of an initializer list compiles to a loop over a stack array)
  const int hi = std::max(std::max(std::max(m, n), std::max(s, w)), e);
  const int lo = std::min(std::min(std::min(m, n), std::min(s, w)), e);
  return 8 * (hi - lo) >= std::max(hi, 64);
}

// FXAA 3.11's per-pixel work (the names follow its source), for a pixel is_edge() passed, in
// integer luma (the search's test |end| >= gradient / 4 as 2 |2 end| >= gradient): false where
// the pixel needs no blend. `c` points at the pixel's luma in a plane of `stride` bytes a row.
bool edge_blend(const std::uint8_t* c, int stride, int x, int y, Blend& out) {
  const int m = c[0];
  int n = c[-stride], s = c[stride];
  const int w = c[-1], e = c[1];
  const int nw = c[-stride - 1], ne = c[-stride + 1], sw = c[stride - 1], se = c[stride + 1];
  const int range = std::max(std::max(std::max(m, n), std::max(s, w)), e) -
                    std::min(std::min(std::min(m, n), std::min(s, w)), e);
  // Second differences across rows (a horizontal edge) and across columns (a vertical one).
  const int edge_horizontal = std::abs(-2 * w + nw + sw) + 2 * std::abs(-2 * m + n + s) + std::abs(-2 * e + ne + se);
  const int edge_vertical = std::abs(-2 * n + nw + ne) + 2 * std::abs(-2 * m + w + e) + std::abs(-2 * s + sw + se);
  const bool horizontal = edge_horizontal >= edge_vertical;

  // Sub-pixel aliasing: how far the pixel stands out from its 3x3 neighbourhood's low-pass
  // (twelve times each side, so exact).
  const int low_pass_12 = 2 * (n + s + w + e) + (nw + ne + sw + se);
  const float subpixel_c =
      std::min(1.f, static_cast<float>(std::abs(low_pass_12 - 12 * m)) / static_cast<float>(12 * range));
  const float subpixel_f = (-2.f * subpixel_c + 3.f) * subpixel_c * subpixel_c;
  const float subpixel = subpixel_f * subpixel_f * kSubpixel;

  // The side of the edge the pixel's neighbour lies on: the steeper of the two.
  if (!horizontal) {
    n = w;
    s = e;
  }
  const int gradient_n = std::abs(n - m), gradient_s = std::abs(s - m);
  const bool pair_n = gradient_n >= gradient_s;
  const int sign = pair_n ? -1 : 1;                  // toward the neighbour: up (left) or down (right)
  const int gradient = std::max(gradient_n, gradient_s);
  const int local_2 = (pair_n ? n : s) + m;          // twice the edge's luma between the two

  // Along the edge, on the line between the pixel's row (column) and its neighbour's: the
  // average of the two, until it differs from the edge's luma by a quarter of the gradient.
  const std::ptrdiff_t along = horizontal ? 1 : stride;
  const std::ptrdiff_t across = horizontal ? sign * static_cast<std::ptrdiff_t>(stride) : sign;
  const auto end_2 = [&](std::ptrdiff_t k) { return c[k * along] + c[k * along + across] - local_2; };
  int dn = 0, dp = 0;  // distances to the two ends searched for
  int end_n = 0, end_p = 0;
  bool done_n = false, done_p = false;
  for (int step : kSteps) {
    if (!done_n) {
      dn += step;
      end_n = end_2(-dn);
      done_n = 2 * std::abs(end_n) >= gradient;
    }
    if (!done_p) {
      dp += step;
      end_p = end_2(dp);
      done_p = 2 * std::abs(end_p) >= gradient;
    }
    if (done_n && done_p) break;
  }
  // The nearer end decides: the pixel is blended only when that end is where the edge turns
  // the pixel's way (the end's luma on the other side of the edge's from the pixel's).
  const bool m_below = 2 * m < local_2;
  const int end = dn < dp ? end_n : end_p;
  const bool good_span = (end < 0) != m_below;
  const float edge_offset =
      good_span ? 0.5f - static_cast<float>(std::min(dn, dp)) / static_cast<float>(dn + dp) : 0.f;
  const float amount = std::max(edge_offset, subpixel);
  if (!(amount > 0.f)) return false;
  out = Blend{x, y, x + (horizontal ? 0 : sign), y + (horizontal ? sign : 0), amount};
  return true;
}

}  // namespace

void fxaa(Image& image, int x0, int y0, int x1, int y1, const std::uint8_t* drawn) {
  // The mask covers the rectangle as given; the work, its part inside the image.
  const std::size_t mask_width = static_cast<std::size_t>(std::max(x1 - x0, 0));
  const int mask_x = std::max(-x0, 0), mask_y = std::max(-y0, 0);  // where the clipped part starts in it
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, image.width);
  y1 = std::min(y1, image.height);
  if (x1 <= x0 || y1 <= y0) return;
  const int w = x1 - x0, h = y1 - y0;
  // The search reaches kFxaaReach pixels along an edge and one across, past the rectangle.
  const LumaPlane luma(image, x0, y0, x1, y1, kFxaaReach + 1);
  const int stride = luma.stride();
  // Which pixels to look at: drawn, or next to one that was (the mask grown by one pixel).
  std::vector<std::uint8_t> near;
  if (drawn) {
    near.assign(static_cast<std::size_t>(w) * h, 0);
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* d = drawn + static_cast<std::size_t>(y + mask_y) * mask_width + mask_x;
      std::uint8_t* out = near.data() + static_cast<std::size_t>(y) * w;
      for (int x = 0; x < w; ++x) {
        if (!d[x]) continue;
        out[x] = 1;
        if (x > 0) out[x - 1] = 1;
        if (x + 1 < w) out[x + 1] = 1;
        if (y > 0) out[x - w] = 1;
        if (y + 1 < h) out[x + w] = 1;
      }
    }
  }
  std::vector<Blend> blends;
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* look = drawn ? near.data() + static_cast<std::size_t>(y) * w : nullptr;
    const std::uint8_t* c = luma.at(x0, y0 + y);
    for (int x = 0; x < w; ++x) {
      if ((look && !look[x]) || !is_edge(c + x, stride)) continue;
      Blend b;
      if (edge_blend(c + x, stride, x0 + x, y0 + y, b)) blends.push_back(b);
    }
  }
  // Each pixel mixes its own and one neighbour's colour as they were before any blend:
  // the new colours are computed first, then written.
  std::vector<std::uint8_t> colours(blends.size() * 3);
  for (std::size_t i = 0; i < blends.size(); ++i) {
    const Blend& b = blends[i];
    const int nx = std::clamp(b.nx, 0, image.width - 1), ny = std::clamp(b.ny, 0, image.height - 1);
    const std::uint8_t* p = image.pixel(b.x, b.y);
    const std::uint8_t* q = image.pixel(nx, ny);
    for (int k = 0; k < 3; ++k) {
      const float mixed = static_cast<float>(p[k]) + (static_cast<float>(q[k]) - static_cast<float>(p[k])) * b.amount;
      colours[3 * i + k] = static_cast<std::uint8_t>(std::clamp(mixed + 0.5f, 0.f, 255.f));
    }
  }
  for (std::size_t i = 0; i < blends.size(); ++i)
    std::copy_n(&colours[3 * i], 3, image.pixel(blends[i].x, blends[i].y));
}

}  // namespace clothsim
