// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/pd_solve_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cstddef>

#include "pd_solve_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::CappedTag<double, 4>;  // one padded row per vector where the target has 4 lanes

// z_j -= sum over e in [start[j], start[j + 1]) of value[e] z_{index[e]}, lanes [c, c + N), for
// every j in the order `step` walks them, with four partial sums (one would chain every
// entry's multiply-add on the last). Forward over L's rows, backward over its columns: both
// gather what they read and store once per row.
HWY_INLINE void Substitute(const int* HWY_RESTRICT start, const int* HWY_RESTRICT index,
                           const double* HWY_RESTRICT value, std::size_t n, std::size_t c, bool forward,
                           double* HWY_RESTRICT z) {
  const D d;
  using V = hn::Vec<D>;
  const auto term = [&](int e) {
    return hn::Mul(hn::Set(d, value[e]), hn::LoadU(d, z + 4 * static_cast<std::size_t>(index[e]) + c));
  };
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = forward ? k : n - 1 - k;
    V s0 = hn::Zero(d), s1 = s0, s2 = s0, s3 = s0;
    int e = start[j];
    for (; e + 4 <= start[j + 1]; e += 4) {
      s0 = hn::Add(s0, term(e)), s1 = hn::Add(s1, term(e + 1));
      s2 = hn::Add(s2, term(e + 2)), s3 = hn::Add(s3, term(e + 3));
    }
    for (; e < start[j + 1]; ++e) s0 = hn::Add(s0, term(e));
    double* at = z + 4 * j + c;
    hn::StoreU(hn::Sub(hn::LoadU(d, at), hn::Add(hn::Add(s0, s1), hn::Add(s2, s3))), d, at);
  }
}

void SolvePadded(const LowerFactor& f, double* HWY_RESTRICT z) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  for (std::size_t c = 0; c < 3; c += N) {
    Substitute(f.row_start, f.row_col, f.row_value, f.n, c, true, z);  // L w = z
    for (std::size_t j = 0; j < f.n; ++j)
      hn::StoreU(hn::Div(hn::LoadU(d, z + 4 * j + c), hn::Set(d, f.pivot[j])), d, z + 4 * j + c);
    Substitute(f.col_start, f.col_row, f.col_value, f.n, c, false, z);  // L^T x = w
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(SolvePadded);

void ldlt_solve_padded(const LowerFactor& f, double* z4) { HWY_DYNAMIC_DISPATCH(SolvePadded)(f, z4); }

}  // namespace clothsim
#endif  // HWY_ONCE
