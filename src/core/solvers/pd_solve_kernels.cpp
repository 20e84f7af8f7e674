// Highway's foreach_target.h compiles this file once per x86 target; HWY_DYNAMIC_DISPATCH
// picks one at run time (as spring_kernels.cpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/solvers/pd_solve_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <type_traits>

#include "pd_solve_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One padded row per vector where the target has 4 lanes (T = float: a 128-bit vector).
template <typename T>
using D = hn::CappedTag<T, 4>;
template <typename T>
using V = hn::Vec<D<T>>;
constexpr int kChunk = 8;  // the most columns of a panel held in registers at once

// Float rows two to a vector where the target has 8 float lanes (AVX2; AVX-512 capped at 8):
// a panel entry's multiplier broadcast to each half (two broadcasts and a blend per two
// entries), so half the multiplies and adds. Each lane still sees the 4-lane code's
// operations in its order (Backward's sums on alternate rows are the halves), so the bits
// match the targets of 4 float lanes.
using D8 = hn::CappedTag<float, 8>;
using V8 = hn::Vec<D8>;
#if HWY_TARGET == HWY_SCALAR
template <typename T>
constexpr bool kPairs = false;  // no half vectors to combine
#else
template <typename T>
constexpr bool kPairs = std::is_same_v<T, float> && hn::MaxLanes(D8()) == 8;
#endif

// Backward's sets of sums on rows i mod Q (K * Q chains); in float at least 2, a pair's halves.
template <typename T, int K>
constexpr int kSets = K == 1 ? 4 : std::is_same_v<T, float> ? 2 : K >= 4 ? 1 : 2;

// t[0] + ... + t[K - 1] as a balanced tree (short dependency chains).
template <int K, class VV>
HWY_INLINE VV Tree(VV* t) {
  #pragma GCC unroll 4
  for (int stride = 1; stride < K; stride *= 2)
    #pragma GCC unroll 8
    for (int b = 0; b + stride < K; b += 2 * stride) t[b] = hn::Add(t[b], t[b + stride]);
  return t[0];
}

// The multipliers of two panel rows for one column: l0 in the lower half, l1 in the upper.
template <class DD = D8>
HWY_INLINE hn::Vec<DD> PairOf(float l0, float l1) {
  const DD d8;
#if HWY_TARGET == HWY_SCALAR
  (void)l1;
  return hn::Set(d8, l0);  // never called (kPairs)
#else
  return hn::ConcatUpperLower(d8, hn::Set(d8, l1), hn::Set(d8, l0));
#endif
}

// One supernode's panel: m rows (the first its own columns) by w columns, row-major.
template <typename T>
struct Panel {
  const T* value;
  const std::int32_t* rows;
  std::size_t m, w;
};

template <typename T>
HWY_INLINE T* row_of(T* z, std::int32_t r, std::size_t c) { return z + 4 * static_cast<std::size_t>(r) + c; }

// sum over b < K of l[b] v[b], added as a balanced tree (short dependency chains).
template <int K, typename T>
HWY_INLINE V<T> RowSum(const T* HWY_RESTRICT l, const V<T>* v) {
  const D<T> d;
  V<T> t[K];
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) t[b] = hn::Mul(hn::Set(d, l[b]), v[b]);
  return Tree<K>(t);
}

// [v | v]: a solved row in both halves.
template <class DD = D8>
HWY_INLINE hn::Vec<DD> Both(V<float> v) {
#if HWY_TARGET == HWY_SCALAR
  return v;  // never called (kPairs)
#else
  return hn::Combine(DD(), v, v);
#endif
}

// Forward's rows below the chunk two at a time (kPairs): rows i0 and i1 of z from l0 and l1.
template <int K>
HWY_INLINE void RowPair(const float* HWY_RESTRICT l0, const float* HWY_RESTRICT l1, const V8* vv,
                        float* HWY_RESTRICT at0, float* HWY_RESTRICT at1) {
#if HWY_TARGET != HWY_SCALAR
  const D8 d8;
  const hn::Half<D8> d4;
  V8 t[K];
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) t[b] = hn::Mul(PairOf(l0[b], l1[b]), vv[b]);
  const V8 r = hn::Sub(hn::Combine(d8, hn::LoadU(d4, at1), hn::LoadU(d4, at0)), Tree<K>(t));
  hn::StoreU(hn::LowerHalf(d4, r), d4, at0);
  hn::StoreU(hn::UpperHalf(d4, r), d4, at1);
#else
  (void)l0, (void)l1, (void)vv, (void)at0, (void)at1;  // never called (kPairs)
#endif
}

// acc[b] += l[b] x for b < K: one row of z used for K columns.
template <int K, typename T>
HWY_INLINE void Gather(const T* HWY_RESTRICT l, V<T> x, V<T>* acc) {
  const D<T> d;
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) acc[b] = hn::Add(acc[b], hn::Mul(hn::Set(d, l[b]), x));
}

// Columns [k0, k0 + K) of L w = z: their triangle first, then every panel row below them
// updated by K multiply-adds with the solved rows held in registers.
template <int K, typename T>
HWY_INLINE void Forward(const Panel<T>& p, std::size_t k0, std::size_t c, T* HWY_RESTRICT z) {
  const D<T> d;
  V<T> v[K];
  #pragma GCC unroll 8
  for (int a = 0; a < K; ++a) {
    const T* l = p.value + (k0 + a) * p.w + k0;
    V<T> s = hn::LoadU(d, row_of(z, p.rows[k0 + a], c));
    #pragma GCC unroll 8
    for (int b = 0; b < a; ++b) s = hn::Sub(s, hn::Mul(hn::Set(d, l[b]), v[b]));
    v[a] = s;
    hn::StoreU(s, d, row_of(z, p.rows[k0 + a], c));
  }
  std::size_t i = k0 + K;
  if constexpr (kPairs<T>) {
    V8 vv[K];
    #pragma GCC unroll 8
    for (int b = 0; b < K; ++b) vv[b] = Both(v[b]);
    for (; i + 2 <= p.m; i += 2)
      RowPair<K>(p.value + i * p.w + k0, p.value + (i + 1) * p.w + k0, vv, row_of(z, p.rows[i], c),
                 row_of(z, p.rows[i + 1], c));
  }
  for (; i < p.m; ++i) {
    T* at = row_of(z, p.rows[i], c);
    hn::StoreU(hn::Sub(hn::LoadU(d, at), RowSum<K, T>(p.value + i * p.w + k0, v)), d, at);
  }
}

// Backward's full groups of Q rows from i two to a vector (kPairs): rows i + 2 q8 and
// i + 2 q8 + 1 summed in one vector's halves, then split into sums q = 2 q8 and 2 q8 + 1 as
// the 4-lane code keeps them. Returns the first row left.
template <int K, int Q>
HWY_INLINE std::size_t BackwardPairs(const Panel<float>& p, std::size_t k0, std::size_t i, std::size_t c, float* HWY_RESTRICT z,
                                     V<float> (&acc)[Q][K]) {
#if HWY_TARGET != HWY_SCALAR
  const D8 d8;
  const hn::Half<D8> d4;
  V8 sum[Q / 2][K];
  #pragma GCC unroll 2
  for (int q = 0; q < Q / 2; ++q)
    #pragma GCC unroll 8
    for (int b = 0; b < K; ++b) sum[q][b] = hn::Zero(d8);
  for (; i + Q <= p.m; i += Q)
    #pragma GCC unroll 2
    for (int q = 0; q < Q / 2; ++q) {
      const std::size_t r = i + 2 * static_cast<std::size_t>(q);
      const V8 x = hn::Combine(d8, hn::LoadU(d4, row_of(z, p.rows[r + 1], c)), hn::LoadU(d4, row_of(z, p.rows[r], c)));
      const float* l0 = p.value + r * p.w + k0;
      const float* l1 = l0 + p.w;
      #pragma GCC unroll 8
      for (int b = 0; b < K; ++b) sum[q][b] = hn::Add(sum[q][b], hn::Mul(PairOf(l0[b], l1[b]), x));
    }
  #pragma GCC unroll 2
  for (int q = 0; q < Q / 2; ++q)
    #pragma GCC unroll 8
    for (int b = 0; b < K; ++b)
      acc[2 * q][b] = hn::LowerHalf(d4, sum[q][b]), acc[2 * q + 1][b] = hn::UpperHalf(d4, sum[q][b]);
#else
  (void)p, (void)k0, (void)c, (void)z, (void)acc;  // never called (kPairs)
#endif
  return i;
}

// Columns [k0, k0 + K) of L^T x = w: every panel row below them loaded once into K sums,
// then their triangle from the last column up.
template <int K, typename T>
HWY_INLINE void Backward(const Panel<T>& p, std::size_t k0, std::size_t c, T* HWY_RESTRICT z) {
  const D<T> d;
  constexpr int Q = kSets<T, K>;
  V<T> acc[Q][K], v[K];
  #pragma GCC unroll 4
  for (int q = 0; q < Q; ++q)
    #pragma GCC unroll 8
    for (int b = 0; b < K; ++b) acc[q][b] = hn::Zero(d);
  std::size_t i = k0 + K;
  if constexpr (kPairs<T>) i = BackwardPairs<K, Q>(p, k0, i, c, z, acc);
  for (; i + Q <= p.m; i += Q)
    #pragma GCC unroll 4
    for (int q = 0; q < Q; ++q) Gather<K, T>(p.value + (i + q) * p.w + k0, hn::LoadU(d, row_of(z, p.rows[i + q], c)), acc[q]);
  for (; i < p.m; ++i) Gather<K, T>(p.value + i * p.w + k0, hn::LoadU(d, row_of(z, p.rows[i], c)), acc[0]);
  #pragma GCC unroll 8
  for (int b = 0; b < K; ++b) {
    // float: sums 0 + 2 and 1 + 3 first, as the pairs' two vectors add before their halves do
    if constexpr (Q == 4 && std::is_same_v<T, float>) acc[0][b] = hn::Add(hn::Add(acc[0][b], acc[2][b]), hn::Add(acc[1][b], acc[3][b]));
    else if constexpr (Q == 4) acc[0][b] = hn::Add(hn::Add(acc[0][b], acc[1][b]), hn::Add(acc[2][b], acc[3][b]));
    if constexpr (Q == 2) acc[0][b] = hn::Add(acc[0][b], acc[1][b]);
  }
  #pragma GCC unroll 8
  for (int a = K - 1; a >= 0; --a) {
    V<T> s = hn::Sub(hn::LoadU(d, row_of(z, p.rows[k0 + a], c)), acc[0][a]);
    #pragma GCC unroll 8
    for (int b = a + 1; b < K; ++b) s = hn::Sub(s, hn::Mul(hn::Set(d, p.value[(k0 + b) * p.w + k0 + a]), v[b]));
    v[a] = s;
    hn::StoreU(s, d, row_of(z, p.rows[k0 + a], c));
  }
}

// Forward or Backward on the K = `width` (1..kChunk) columns from k0, K fixed at compile time.
template <bool kForward, typename T, int K = kChunk>
HWY_INLINE void Columns(const Panel<T>& p, std::size_t k0, std::size_t width, std::size_t c, T* HWY_RESTRICT z) {
  if constexpr (K > 1) {
    if (width < static_cast<std::size_t>(K)) return Columns<kForward, T, K - 1>(p, k0, width, c, z);
  }
  if constexpr (kForward) Forward<K, T>(p, k0, c, z);
  else Backward<K, T>(p, k0, c, z);
}

template <typename T>
Panel<T> panel(const BasicSupernodes<T>& f, std::size_t s) {
  const std::size_t r0 = static_cast<std::size_t>(f.row_start[s]);
  return {f.value.data() + f.value_start[s], f.rows.data() + r0, static_cast<std::size_t>(f.row_start[s + 1]) - r0,
          static_cast<std::size_t>(f.first[s + 1] - f.first[s])};
}

// Chunk q of a panel of width w cut into ceil(w / kChunk) chunks of near-equal widths (no
// thin last chunk walking every row below for one or two columns): its first column.
HWY_INLINE std::size_t ChunkStart(std::size_t w, std::size_t chunks, std::size_t q) { return q * w / chunks; }

template <typename T>
void Solve(const BasicSupernodes<T>& f, T* HWY_RESTRICT z) {
  const D<T> d;
  const std::size_t N = hn::Lanes(d), S = f.size();
  for (std::size_t c = 0; c < 3; c += N) {
    for (std::size_t s = 0; s < S; ++s) {  // L w = z
      const Panel<T> p = panel(f, s);
      const std::size_t chunks = (p.w + kChunk - 1) / kChunk;
      for (std::size_t q = 0; q < chunks; ++q) {
        const std::size_t k0 = ChunkStart(p.w, chunks, q);
        Columns<true, T>(p, k0, ChunkStart(p.w, chunks, q + 1) - k0, c, z);
      }
    }
    for (std::size_t j = 0; j < f.n; ++j)
      hn::StoreU(hn::Div(hn::LoadU(d, z + 4 * j + c), hn::Set(d, f.pivot[j])), d, z + 4 * j + c);
    for (std::size_t s = S; s-- > 0;) {  // L^T x = w
      const Panel<T> p = panel(f, s);
      const std::size_t chunks = (p.w + kChunk - 1) / kChunk;
      for (std::size_t q = chunks; q-- > 0;) {
        const std::size_t k0 = ChunkStart(p.w, chunks, q);
        Columns<false, T>(p, k0, ChunkStart(p.w, chunks, q + 1) - k0, c, z);
      }
    }
  }
}

void SolveSupernodal(const Supernodes& f, double* HWY_RESTRICT z) { Solve(f, z); }
void SolveSupernodalFloat(const SupernodesF& f, float* HWY_RESTRICT z) { Solve(f, z); }

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(SolveSupernodal);

HWY_EXPORT(SolveSupernodalFloat);

void ldlt_solve_padded(const Supernodes& f, double* z4) { HWY_DYNAMIC_DISPATCH(SolveSupernodal)(f, z4); }
void ldlt_solve_padded(const SupernodesF& f, float* z4) { HWY_DYNAMIC_DISPATCH(SolveSupernodalFloat)(f, z4); }

}  // namespace clothsim
#endif  // HWY_ONCE
