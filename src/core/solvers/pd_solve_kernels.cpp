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

// Lanes [c, c + N) of every row: L w = z by columns of L, w / D, then L^T x = w by rows of
// L^T with four partial sums (one would chain every entry's multiply-add on the last).
void SolveLanes(const int* HWY_RESTRICT start, const int* HWY_RESTRICT row, const double* HWY_RESTRICT value,
                const double* HWY_RESTRICT pivot, std::size_t n, std::size_t c, double* HWY_RESTRICT z) {
  const D d;
  using V = hn::Vec<D>;
  for (std::size_t j = 0; j < n; ++j) {
    const V zj = hn::LoadU(d, z + 4 * j + c);
    for (int e = start[j]; e < start[j + 1]; ++e) {
      double* at = z + 4 * static_cast<std::size_t>(row[e]) + c;
      hn::StoreU(hn::Sub(hn::LoadU(d, at), hn::Mul(hn::Set(d, value[e]), zj)), d, at);
    }
  }
  for (std::size_t j = 0; j < n; ++j)
    hn::StoreU(hn::Div(hn::LoadU(d, z + 4 * j + c), hn::Set(d, pivot[j])), d, z + 4 * j + c);
  const auto term = [&](int e) { return hn::Mul(hn::Set(d, value[e]), hn::LoadU(d, z + 4 * static_cast<std::size_t>(row[e]) + c)); };
  for (std::size_t j = n; j-- > 0;) {
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

void SolvePadded(const int* HWY_RESTRICT start, const int* HWY_RESTRICT row, const double* HWY_RESTRICT value,
                 const double* HWY_RESTRICT pivot, std::size_t n, double* HWY_RESTRICT z) {
  const std::size_t N = hn::Lanes(D());
  for (std::size_t c = 0; c < 3; c += N) SolveLanes(start, row, value, pivot, n, c, z);
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(SolvePadded);

void ldlt_solve_padded(const int* start, const int* row, const double* value, const double* d, std::size_t n,
                       double* z4) {
  HWY_DYNAMIC_DISPATCH(SolvePadded)(start, row, value, d, n, z4);
}

}  // namespace clothsim
#endif  // HWY_ONCE
