// Highway's foreach_target.h compiles this file once per x86 target (SCALAR, SSSE3, SSE4,
// AVX2, AVX3), each copy in its own namespace; HWY_EXPORT / HWY_DYNAMIC_DISPATCH pick the copy
// at run time (spring_kernels.cpp does the same).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/linear/block_factor_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "block_factor_kernels.h"

HWY_BEFORE_NAMESPACE();
namespace clothsim {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Up to four lanes: one padded column per vector on AVX2 and AVX-512 (which then runs 256-bit
// vectors), two halves on SSE4, four single lanes on SCALAR; each lane's arithmetic is the same.
using D = hn::CappedTag<double, kPaddedVector>;
using V = hn::Vec<D>;

// c0 s0 + c1 s1 + c2 s2, in that order (the one order every target uses).
HWY_INLINE V Combine(V c0, V c1, V c2, V s0, V s1, V s2) {
  return hn::Add(hn::Add(hn::Mul(c0, s0), hn::Mul(c1, s1)), hn::Mul(c2, s2));
}

void FactorRow(int k, const int* HWY_RESTRICT pattern, int count, double* HWY_RESTRICT y,
               const int* HWY_RESTRICT column_start, int* HWY_RESTRICT filled,
               int* HWY_RESTRICT row, double* HWY_RESTRICT value,
               const double* HWY_RESTRICT d_inverse, double* HWY_RESTRICT d) {
  const D dd;
  const std::size_t N = hn::Lanes(dd);
  for (int t = 0; t < count; ++t) {
    const int i = pattern[t];
    // Y_i, taken out of y (which must be zero again for the next row).
    double* HWY_RESTRICT yi_at = y + kPaddedBlock * i;
    double yi[kPaddedBlock];
    for (int e = 0; e < kPaddedBlock; ++e) {
      yi[e] = yi_at[e];
      yi_at[e] = 0.0;
    }
    // Broadcasts of Y_i's entries: s[a][b] = Y_i(a, b) (column b is yi[4 b .. 4 b + 2]).
    const V s00 = hn::Set(dd, yi[0]), s10 = hn::Set(dd, yi[1]), s20 = hn::Set(dd, yi[2]);
    const V s01 = hn::Set(dd, yi[4]), s11 = hn::Set(dd, yi[5]), s21 = hn::Set(dd, yi[6]);
    const V s02 = hn::Set(dd, yi[8]), s12 = hn::Set(dd, yi[9]), s22 = hn::Set(dd, yi[10]);

    // y_r -= L(r, i) Y_i over column i's blocks so far: column b of the product is
    // L.col(0) Y(0, b) + L.col(1) Y(1, b) + L.col(2) Y(2, b).
    const int begin = column_start[i], end = begin + filled[i];
    for (std::size_t o = 0; o < kPaddedVector; o += N) {
      for (int p = begin; p < end; ++p) {
        const double* HWY_RESTRICT L = value + kBlock * p + o;
        double* HWY_RESTRICT Y = y + kPaddedBlock * row[p] + o;
        const V c0 = hn::LoadU(dd, L), c1 = hn::LoadU(dd, L + 3), c2 = hn::LoadU(dd, L + 6);
        hn::StoreU(hn::Sub(hn::LoadU(dd, Y), Combine(c0, c1, c2, s00, s10, s20)), dd, Y);
        hn::StoreU(hn::Sub(hn::LoadU(dd, Y + 4), Combine(c0, c1, c2, s01, s11, s21)), dd, Y + 4);
        hn::StoreU(hn::Sub(hn::LoadU(dd, Y + 8), Combine(c0, c1, c2, s02, s12, s22)), dd, Y + 8);
      }
    }

    // L(k, i) = Y_i^T D_i^-1, formed as its transpose D_i^-1 Y_i (D_i^-1 is symmetric up to
    // rounding; either is the factor of a matrix within rounding of A).
    const double* HWY_RESTRICT Di = d_inverse + kBlock * i;
    double lt[kPaddedBlock];
    for (std::size_t o = 0; o < kPaddedVector; o += N) {
      const V c0 = hn::LoadU(dd, Di + o), c1 = hn::LoadU(dd, Di + 3 + o), c2 = hn::LoadU(dd, Di + 6 + o);
      hn::StoreU(Combine(c0, c1, c2, s00, s10, s20), dd, lt + o);
      hn::StoreU(Combine(c0, c1, c2, s01, s11, s21), dd, lt + 4 + o);
      hn::StoreU(Combine(c0, c1, c2, s02, s12, s22), dd, lt + 8 + o);
    }
    double* HWY_RESTRICT l = value + kBlock * end;
    for (int c = 0; c < 3; ++c)  // column c of L(k, i) is row c of its transpose
      for (int r = 0; r < 3; ++r) l[3 * c + r] = lt[4 * r + c];
    row[end] = k;
    ++filled[i];

    // D_k -= L(k, i) Y_i.
    for (std::size_t o = 0; o < kPaddedVector; o += N) {
      const V c0 = hn::LoadU(dd, l + o), c1 = hn::LoadU(dd, l + 3 + o), c2 = hn::LoadU(dd, l + 6 + o);
      hn::StoreU(hn::Sub(hn::LoadU(dd, d + o), Combine(c0, c1, c2, s00, s10, s20)), dd, d + o);
      hn::StoreU(hn::Sub(hn::LoadU(dd, d + 4 + o), Combine(c0, c1, c2, s01, s11, s21)), dd, d + 4 + o);
      hn::StoreU(hn::Sub(hn::LoadU(dd, d + 8 + o), Combine(c0, c1, c2, s02, s12, s22)), dd, d + 8 + o);
    }
  }
}

void FactorSolve(const PaddedFactor& f, const int* HWY_RESTRICT order, const double* HWY_RESTRICT r,
                 double* HWY_RESTRICT z, double* HWY_RESTRICT w) {
  const D dd;
  const std::size_t N = hn::Lanes(dd);
  const int B = f.bodies;
  const int* HWY_RESTRICT start = f.column_start;
  const int* HWY_RESTRICT row = f.row;
  const double* HWY_RESTRICT value = f.value;
  for (int k = 0; k < B; ++k) {  // into the factor's order, padded
    const double* from = r + 3 * static_cast<std::size_t>(order[k]);
    double* to = w + kPaddedVector * k;
    to[0] = from[0];
    to[1] = from[1];
    to[2] = from[2];
    to[3] = 0.0;
  }
  // L u = w, by columns: w_r -= L(r, j) u_j.
  for (int j = 0; j < B; ++j) {
    const double* uj = w + kPaddedVector * j;
    const V u0 = hn::Set(dd, uj[0]), u1 = hn::Set(dd, uj[1]), u2 = hn::Set(dd, uj[2]);
    for (std::size_t o = 0; o < kPaddedVector; o += N) {
      for (int p = start[j]; p < start[j + 1]; ++p) {
        const double* HWY_RESTRICT L = value + kBlock * p + o;
        double* HWY_RESTRICT W = w + kPaddedVector * row[p] + o;
        const V c0 = hn::LoadU(dd, L), c1 = hn::LoadU(dd, L + 3), c2 = hn::LoadU(dd, L + 6);
        hn::StoreU(hn::Sub(hn::LoadU(dd, W), Combine(c0, c1, c2, u0, u1, u2)), dd, W);
      }
    }
  }
  // D v = u.
  for (int j = 0; j < B; ++j) {
    double* HWY_RESTRICT uj = w + kPaddedVector * j;
    const V u0 = hn::Set(dd, uj[0]), u1 = hn::Set(dd, uj[1]), u2 = hn::Set(dd, uj[2]);
    const double* HWY_RESTRICT Dj = f.d_inverse + kBlock * j;
    for (std::size_t o = 0; o < kPaddedVector; o += N) {
      const V c0 = hn::LoadU(dd, Dj + o), c1 = hn::LoadU(dd, Dj + 3 + o), c2 = hn::LoadU(dd, Dj + 6 + o);
      hn::StoreU(Combine(c0, c1, c2, u0, u1, u2), dd, uj + o);
    }
  }
  // L^T z = v, by columns from the last: z_j = v_j - sum_p L(row_p, j)^T z_row_p. Entry a of
  // a block's transposed product is column a . z: summed lane by lane over the column's blocks,
  // then across the lanes in a fixed order.
  for (int j = B - 1; j >= 0; --j) {
    double sum[3][kPaddedVector];
    for (std::size_t o = 0; o < kPaddedVector; o += N) {
      V a0 = hn::Zero(dd), a1 = hn::Zero(dd), a2 = hn::Zero(dd);
      for (int p = start[j]; p < start[j + 1]; ++p) {
        const double* HWY_RESTRICT L = value + kBlock * p + o;
        const V zr = hn::LoadU(dd, w + kPaddedVector * row[p] + o);
        a0 = hn::Add(a0, hn::Mul(hn::LoadU(dd, L), zr));
        a1 = hn::Add(a1, hn::Mul(hn::LoadU(dd, L + 3), zr));
        a2 = hn::Add(a2, hn::Mul(hn::LoadU(dd, L + 6), zr));
      }
      hn::StoreU(a0, dd, sum[0] + o);
      hn::StoreU(a1, dd, sum[1] + o);
      hn::StoreU(a2, dd, sum[2] + o);
    }
    double* vj = w + kPaddedVector * j;
    for (int a = 0; a < 3; ++a) vj[a] -= (sum[a][0] + sum[a][1]) + sum[a][2];
  }
  for (int k = 0; k < B; ++k) {  // back to the bodies' order
    const double* from = w + kPaddedVector * k;
    double* to = z + 3 * static_cast<std::size_t>(order[k]);
    to[0] = from[0];
    to[1] = from[1];
    to[2] = from[2];
  }
}

const char* FactorTargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace clothsim
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace clothsim {

HWY_EXPORT(FactorRow);
HWY_EXPORT(FactorSolve);
HWY_EXPORT(FactorTargetName);

void factor_row(int k, const int* pattern, int count, double* y, const int* column_start,
                int* filled, int* row, double* value, const double* d_inverse, double* d) {
  HWY_DYNAMIC_DISPATCH(FactorRow)(k, pattern, count, y, column_start, filled, row, value,
                                  d_inverse, d);
}

void factor_solve(const PaddedFactor& factor, const int* order, const double* r, double* z,
                  double* w) {
  HWY_DYNAMIC_DISPATCH(FactorSolve)(factor, order, r, z, w);
}

const char* block_factor_target() { return HWY_DYNAMIC_DISPATCH(FactorTargetName)(); }

}  // namespace clothsim
#endif  // HWY_ONCE
