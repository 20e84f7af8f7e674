// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/pd_solve_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

#include "pd_solve_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::CappedTag<double, 4>;  // one padded row per vector where the target has 4 lanes
using V = hn::Vec<D>;
constexpr int kChunk = 8;  // the most columns of a panel held in registers at once

// One supernode's panel: m rows (the first its own columns) by w columns, row-major.
struct Panel {
  const double* value;
  const std::int32_t* rows;
  std::size_t m, w;
};

HWY_INLINE double* row_of(double* z, std::int32_t r, std::size_t c) { return z + 4 * static_cast<std::size_t>(r) + c; }

// sum over b < K of l[b] v[b], added as a balanced tree (short dependency chains).
template <int K>
HWY_INLINE V RowSum(const double* HWY_RESTRICT l, const V* v) {
  const D d;
  V t[K];
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) t[b] = hn::Mul(hn::Set(d, l[b]), v[b]);
  #pragma GCC unroll 4
  for (int stride = 1; stride < K; stride *= 2)
    #pragma GCC unroll 8
    for (int b = 0; b + stride < K; b += 2 * stride) t[b] = hn::Add(t[b], t[b + stride]);
  return t[0];
}

// acc[b] += l[b] x for b < K: one row of z used for K columns.
template <int K>
HWY_INLINE void Gather(const double* HWY_RESTRICT l, V x, V* acc) {
  const D d;
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) acc[b] = hn::Add(acc[b], hn::Mul(hn::Set(d, l[b]), x));
}

// Columns [k0, k0 + K) of L w = z: their triangle first, then every panel row below them
// updated by K multiply-adds with the solved rows held in registers.
template <int K>
HWY_INLINE void Forward(const Panel& p, std::size_t k0, std::size_t c, double* HWY_RESTRICT z) {
  const D d;
  V v[K];
  #pragma GCC unroll 8
  for (int a = 0; a < K; ++a) {
    const double* l = p.value + (k0 + a) * p.w + k0;
    V s = hn::LoadU(d, row_of(z, p.rows[k0 + a], c));
    #pragma GCC unroll 8
    for (int b = 0; b < a; ++b) s = hn::Sub(s, hn::Mul(hn::Set(d, l[b]), v[b]));
    v[a] = s;
    hn::StoreU(s, d, row_of(z, p.rows[k0 + a], c));
  }
  for (std::size_t i = k0 + K; i < p.m; ++i) {
    double* at = row_of(z, p.rows[i], c);
    hn::StoreU(hn::Sub(hn::LoadU(d, at), RowSum<K>(p.value + i * p.w + k0, v)), d, at);
  }
}

// Columns [k0, k0 + K) of L^T x = w: every panel row below them loaded once into K sums,
// then their triangle from the last column up.
template <int K>
HWY_INLINE void Backward(const Panel& p, std::size_t k0, std::size_t c, double* HWY_RESTRICT z) {
  const D d;
  constexpr int Q = K >= 4 ? 1 : K == 1 ? 4 : 2;  // sets of sums on alternate rows: K * Q chains
  V acc[Q][K], v[K];
  #pragma GCC unroll 4
  for (int q = 0; q < Q; ++q)
    #pragma GCC unroll 8
    for (int b = 0; b < K; ++b) acc[q][b] = hn::Zero(d);
  std::size_t i = k0 + K;
  for (; i + Q <= p.m; i += Q)
    #pragma GCC unroll 4
    for (int q = 0; q < Q; ++q) Gather<K>(p.value + (i + q) * p.w + k0, hn::LoadU(d, row_of(z, p.rows[i + q], c)), acc[q]);
  for (; i < p.m; ++i) Gather<K>(p.value + i * p.w + k0, hn::LoadU(d, row_of(z, p.rows[i], c)), acc[0]);
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) {
    if constexpr (Q == 4) acc[0][b] = hn::Add(hn::Add(acc[0][b], acc[1][b]), hn::Add(acc[2][b], acc[3][b]));
    if constexpr (Q == 2) acc[0][b] = hn::Add(acc[0][b], acc[1][b]);
  }
  #pragma GCC unroll 8
  for (int a = K - 1; a >= 0; --a) {
    V s = hn::Sub(hn::LoadU(d, row_of(z, p.rows[k0 + a], c)), acc[0][a]);
    #pragma GCC unroll 8
    for (int b = a + 1; b < K; ++b) s = hn::Sub(s, hn::Mul(hn::Set(d, p.value[(k0 + b) * p.w + k0 + a]), v[b]));
    v[a] = s;
    hn::StoreU(s, d, row_of(z, p.rows[k0 + a], c));
  }
}

// Forward or Backward on the K = `width` (1..kChunk) columns from k0, K fixed at compile time.
template <bool kForward, int K = kChunk>
HWY_INLINE void Columns(const Panel& p, std::size_t k0, std::size_t width, std::size_t c, double* HWY_RESTRICT z) {
  if constexpr (K > 1) {
    if (width < static_cast<std::size_t>(K)) return Columns<kForward, K - 1>(p, k0, width, c, z);
  }
  if constexpr (kForward) Forward<K>(p, k0, c, z);
  else Backward<K>(p, k0, c, z);
}

Panel panel(const Supernodes& f, std::size_t s) {
  const std::size_t r0 = static_cast<std::size_t>(f.row_start[s]);
  return {f.value.data() + f.value_start[s], f.rows.data() + r0, static_cast<std::size_t>(f.row_start[s + 1]) - r0,
          static_cast<std::size_t>(f.first[s + 1] - f.first[s])};
}

// Chunk q of a panel of width w cut into ceil(w / kChunk) chunks of near-equal widths (no
// thin last chunk walking every row below for one or two columns): its first column.
HWY_INLINE std::size_t ChunkStart(std::size_t w, std::size_t chunks, std::size_t q) { return q * w / chunks; }

void SolveSupernodal(const Supernodes& f, double* HWY_RESTRICT z) {
  const D d;
  const std::size_t N = hn::Lanes(d), S = f.size();
  for (std::size_t c = 0; c < 3; c += N) {
    for (std::size_t s = 0; s < S; ++s) {  // L w = z
      const Panel p = panel(f, s);
      const std::size_t chunks = (p.w + kChunk - 1) / kChunk;
      for (std::size_t q = 0; q < chunks; ++q) {
        const std::size_t k0 = ChunkStart(p.w, chunks, q);
        Columns<true>(p, k0, ChunkStart(p.w, chunks, q + 1) - k0, c, z);
      }
    }
    for (std::size_t j = 0; j < f.n; ++j)
      hn::StoreU(hn::Div(hn::LoadU(d, z + 4 * j + c), hn::Set(d, f.pivot[j])), d, z + 4 * j + c);
    for (std::size_t s = S; s-- > 0;) {  // L^T x = w
      const Panel p = panel(f, s);
      const std::size_t chunks = (p.w + kChunk - 1) / kChunk;
      for (std::size_t q = chunks; q-- > 0;) {
        const std::size_t k0 = ChunkStart(p.w, chunks, q);
        Columns<false>(p, k0, ChunkStart(p.w, chunks, q + 1) - k0, c, z);
      }
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(SolveSupernodal);

void ldlt_solve_padded(const Supernodes& f, double* z4) { HWY_DYNAMIC_DISPATCH(SolveSupernodal)(f, z4); }

}  // namespace clothsim
#endif  // HWY_ONCE
