#include "multigrid_preconditioner.h"

#include <algorithm>
#include <cmath>

namespace clothsim {

namespace {

// One axis of n particles halved: the coarse points are the even indices and the last (so a
// sheet of even side keeps its far edge); an odd index between two coarse points is their
// mean. Returns, per fine index, up to two (coarse index, weight); `coarse_n` the count.
struct AxisEntry {
  int c[2];
  double w[2];
  int count;
};
std::vector<AxisEntry> halve_axis(int n, int& coarse_n) {
  std::vector<AxisEntry> out(n);
  if (n <= 2) {  // nothing to halve: the axis is kept
    coarse_n = n;
    for (int i = 0; i < n; ++i) out[i] = {{i, 0}, {1.0, 0.0}, 1};
    return out;
  }
  const bool last_odd = (n - 1) % 2 == 1;
  coarse_n = (n + 1) / 2 + (last_odd ? 1 : 0);
  for (int i = 0; i < n; ++i) {
    if (i % 2 == 0) out[i] = {{i / 2, 0}, {1.0, 0.0}, 1};
    else if (i == n - 1) out[i] = {{coarse_n - 1, 0}, {1.0, 0.0}, 1};
    else out[i] = {{(i - 1) / 2, (i + 1) / 2}, {0.5, 0.5}, 2};
  }
  return out;
}

// The blocks one Gauss-Seidel sweep or a mat-vec visits, of the finest mat-vec's.
double visits(const BlockRows& M) { return static_cast<double>(M.col.size()); }

}  // namespace

void BlockRows::multiply(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& y) const {
  const int n = size();
  y.resize(3, n);
  const double* xs = x.data();
  for (int i = 0; i < n; ++i) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    for (int e = start[i]; e < start[i + 1]; ++e) {
      const double* m = value[e].data();  // column-major
      const double* v = xs + 3 * col[e];
      s0 += m[0] * v[0] + m[3] * v[1] + m[6] * v[2];
      s1 += m[1] * v[0] + m[4] * v[1] + m[7] * v[2];
      s2 += m[2] * v[0] + m[5] * v[1] + m[8] * v[2];
    }
    y(0, i) = s0, y(1, i) = s1, y(2, i) = s2;
  }
}

GridTransfer grid_transfer(int nx, int ny, int others) {
  GridTransfer t;
  int cx = 0, cy = 0;
  const std::vector<AxisEntry> ax = halve_axis(nx, cx), ay = halve_axis(ny, cy);
  t.coarse_nx = cx;
  t.coarse_ny = cy;
  t.fine_bodies = nx * ny + others;
  t.coarse_bodies = cx * cy + others;
  t.start.assign(1, 0);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {  // the tensor product of the two axes' weights
      for (int b = 0; b < ay[j].count; ++b)
        for (int a = 0; a < ax[i].count; ++a) {
          t.coarse.push_back(ay[j].c[b] * cx + ax[i].c[a]);
          t.weight.push_back(ay[j].w[b] * ax[i].w[a]);
        }
      t.start.push_back(static_cast<int>(t.coarse.size()));
    }
  for (int k = 0; k < others; ++k) {  // bodies past the grid: themselves
    t.coarse.push_back(cx * cy + k);
    t.weight.push_back(1.0);
    t.start.push_back(static_cast<int>(t.coarse.size()));
  }
  // The transpose, by coarse body (counting sort keeps fine bodies in order).
  t.t_start.assign(t.coarse_bodies + 1, 0);
  for (int c : t.coarse) ++t.t_start[c + 1];
  for (int c = 0; c < t.coarse_bodies; ++c) t.t_start[c + 1] += t.t_start[c];
  t.t_fine.resize(t.coarse.size());
  t.t_weight.resize(t.coarse.size());
  std::vector<int> next(t.t_start.begin(), t.t_start.end() - 1);
  for (int i = 0; i < t.fine_bodies; ++i)
    for (int e = t.start[i]; e < t.start[i + 1]; ++e) {
      const int at = next[t.coarse[e]]++;
      t.t_fine[at] = i;
      t.t_weight[at] = t.weight[e];
    }
  return t;
}

void MultigridPreconditioner::analyse(const SpringBlockMatrix& A, int grid_nx, int grid_ny) {
  const int B = A.num_bodies();
  transfer_.clear();
  int nx = grid_nx, ny = grid_ny, others = B - grid_nx * grid_ny;
  if (grid_nx < 1 || grid_ny < 1 || others < 0) nx = 0, ny = 0, others = B;  // no grid: one level
  while (nx * ny + others > kCoarsest && (nx > 2 || ny > 2)) {
    transfer_.push_back(grid_transfer(nx, ny, others));
    nx = transfer_.back().coarse_nx;
    ny = transfer_.back().coarse_ny;
  }
  // The finest level's pattern: the diagonal first in each row, then a block per spring end.
  op_.assign(transfer_.size() + 1, BlockRows{});
  BlockRows& F = op_[0];
  F.start.assign(B + 1, 0);
  for (int i = 0; i < B; ++i) F.start[i + 1] = 1;
  for (std::size_t s = 0; s < A.num_springs(); ++s) ++F.start[A.a[s] + 1], ++F.start[A.b[s] + 1];
  for (int i = 0; i < B; ++i) F.start[i + 1] += F.start[i];
  F.col.resize(F.start[B]);
  F.value.resize(F.start[B]);
  std::vector<int> next(F.start.begin(), F.start.end() - 1);
  for (int i = 0; i < B; ++i) F.col[next[i]++] = i;
  spring_ab_.resize(A.num_springs());
  spring_ba_.resize(A.num_springs());
  for (std::size_t s = 0; s < A.num_springs(); ++s) {
    spring_ab_[s] = next[A.a[s]]++;
    F.col[spring_ab_[s]] = A.b[s];
    spring_ba_[s] = next[A.b[s]]++;
    F.col[spring_ba_[s]] = A.a[s];
  }
  x_.assign(op_.size(), Eigen::Matrix3Xd());
  b_ = t_ = x_;
  marker_.clear();
  route_.clear();
  fixed_.clear();
  fine_.slot.clear();  // the spring form's pattern: copied again at the next build
  analysed_ = true;
  ready_ = false;
}

// S A S + (I - S) from A's projected blocks (S_i = I - n n^T on held bodies).
void MultigridPreconditioner::load_finest(const SpringBlockMatrix& A, const VelocityFilter& filter) {
  BlockRows& F = op_[0];
  const int B = A.num_bodies();
  for (int i = 0; i < B; ++i) F.value[F.start[i]] = A.diag_projected[i];
  for (std::size_t s = 0; s < A.num_springs(); ++s) F.value[spring_ab_[s]] = F.value[spring_ba_[s]] = A.off_projected(s);
  held_ = filter;
  for (std::size_t c = 0; c < filter.size(); ++c) {
    const int i = filter.body[c];
    const Mat3 S = Mat3::Identity() - filter.normal[c] * filter.normal[c].transpose();
    // Row i times S on the left, column i times S on the right (the column's blocks sit in
    // the rows of i's neighbours, at the entries whose col is i).
    for (int e = F.start[i]; e < F.start[i + 1]; ++e) {
      F.value[e] = S * F.value[e];
      const int j = F.col[e];
      if (j == i) continue;
      for (int f = F.start[j]; f < F.start[j + 1]; ++f)
        if (F.col[f] == i) F.value[f] = F.value[f] * S;
    }
    Mat3& D = F.value[F.start[i]];
    D = D * S + (Mat3::Identity() - S);
  }
}

// C = P^T A P: coarse row I gathers, from each fine row i it interpolates to, A(i, j) spread
// over the coarse bodies j interpolates from (Gustavson's row-by-row product with a marker).
// The pattern and where each product lands (route_) are found once per set of immovable
// bodies; a build then only runs the same loops adding values.
void MultigridPreconditioner::galerkin(int l, bool symbolic) {
  const BlockRows& A = op_[l];
  const GridTransfer& P = transfer_[l];
  BlockRows& C = op_[l + 1];
  std::vector<int>& route = route_[l];
  const bool finest = l == 0;
  const auto fixed = [&](int i) { return finest && fixed_[i]; };
  if (symbolic) {
    C.start.assign(1, 0);
    C.col.clear();
    route.clear();
    marker_.assign(P.coarse_bodies, -1);
  } else {
    std::fill(C.value.begin(), C.value.end(), Mat3::Zero());
  }
  std::size_t k = 0;
  for (int I = 0; I < P.coarse_bodies; ++I) {
    const int row = symbolic ? static_cast<int>(C.col.size()) : C.start[I];
    if (symbolic) {  // the diagonal first, as on the finest level (the smoother skips it so)
      marker_[I] = row;
      C.col.push_back(I);
    }
    for (int p = P.t_start[I]; p < P.t_start[I + 1]; ++p) {
      const int i = P.t_fine[p];
      if (fixed(i)) continue;
      const double wi = P.t_weight[p];
      for (int e = A.start[i]; e < A.start[i + 1]; ++e) {
        const int j = A.col[e];
        if (fixed(j)) continue;
        for (int q = P.start[j]; q < P.start[j + 1]; ++q) {
          if (symbolic) {
            const int J = P.coarse[q];
            if (marker_[J] < row) {
              marker_[J] = static_cast<int>(C.col.size());
              C.col.push_back(J);
            }
            route.push_back(marker_[J]);
          } else {
            C.value[route[k++]] += (wi * P.weight[q]) * A.value[e];
          }
        }
      }
    }
    if (symbolic) {
      if (C.col.size() == static_cast<std::size_t>(row) + 1 && P.t_start[I] < P.t_start[I + 1] &&
          std::all_of(P.t_fine.begin() + P.t_start[I], P.t_fine.begin() + P.t_start[I + 1], fixed))
        route.push_back(-1 - row);  // every fine body it reaches is immovable: an identity row
      C.start.push_back(static_cast<int>(C.col.size()));
    } else if (k < route.size() && route[k] < 0) {
      C.value[-1 - route[k++]] = Mat3::Identity();
    }
  }
  if (symbolic) C.value.assign(C.col.size(), Mat3::Zero());
}

bool MultigridPreconditioner::invert_diagonals(BlockRows& M) {
  const int n = M.size();
  M.diag_inverse.resize(n);
  for (int i = 0; i < n; ++i) {
    Eigen::LLT<Mat3> llt(M.value[M.start[i]]);  // the diagonal block, first in its row
    if (llt.info() != Eigen::Success) return false;
    M.diag_inverse[i] = llt.solve(Mat3::Identity());
  }
  return true;
}

bool MultigridPreconditioner::build(const SpringBlockMatrix& A, const VelocityFilter& filter,
                                    const Eigen::VectorXd& inv_mass) {
  ready_ = false;
  const int B = A.num_bodies();
  std::vector<std::uint8_t> fixed(B);
  for (int i = 0; i < B; ++i) fixed[i] = inv_mass.size() == B && inv_mass[i] == 0.0;
  const bool symbolic = route_.size() + 1 != op_.size() || fixed != fixed_;  // first, or pins changed
  fixed_.swap(fixed);
  if (symbolic) route_.assign(transfer_.size(), {});
  load_finest(A, filter);
  for (std::size_t l = 0; l + 1 < op_.size(); ++l) {
    if (symbolic) galerkin(static_cast<int>(l), true);
    galerkin(static_cast<int>(l), false);
  }
  for (BlockRows& M : op_)
    if (!invert_diagonals(M)) return false;
  if (options_.fine == FineSmoother::Chebyshev && op_.size() > 1) {
    load_spring_form(A);
    estimate_lambda_max();
    if (!(lambda_max_ > 0.0) || !std::isfinite(lambda_max_)) return false;
  }
  // The coarsest level, dense, factored once.
  const BlockRows& Z = op_.back();
  const int n = Z.size();
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i)
    for (int e = Z.start[i]; e < Z.start[i + 1]; ++e) dense.block<3, 3>(3 * i, 3 * Z.col[e]) += Z.value[e];
  coarsest_.compute(dense);
  if (coarsest_.info() != Eigen::Success) return false;
  // Costs in finest mat-vec blocks: pre and post sweeps and a residual per level but the last
  // (Chebyshev on the finest level: 2 degree mat-vecs).
  const double unit = std::max(1.0, visits(op_[0]));
  const bool polynomial = options_.fine == FineSmoother::Chebyshev;
  double cycle = 0.0, galerkin_work = 0.0;
  for (std::size_t l = 0; l + 1 < op_.size(); ++l) {
    cycle += l == 0 && polynomial ? 2.0 * options_.degree * unit : 3.0 * visits(op_[l]);
    galerkin_work += visits(op_[l]) * 4.0;  // each block spread over about 2 x 2 coarse pairs
  }
  cycle += 3.0 * n * 3.0 * n / 9.0;  // the dense triangular solves, in block units
  cycle_cost_ = cycle / unit;
  build_cost_ = (galerkin_work + 3.0 * n * 3.0 * n * 3.0 * n / 27.0) / unit;
  ready_ = true;
  return true;
}

// One V-cycle on level l from x = 0 for the right side b_[l].
void MultigridPreconditioner::cycle(int l) const {
  const BlockRows& A = op_[l];
  const int n = A.size();
  Eigen::Matrix3Xd& x = x_[l];
  const Eigen::Matrix3Xd& b = b_[l];
  x.setZero(3, n);
  if (l + 1 == static_cast<int>(op_.size())) {
    Eigen::Map<Eigen::VectorXd> flat(x.data(), 3 * n);
    flat = coarsest_.solve(Eigen::Map<const Eigen::VectorXd>(b.data(), 3 * n));
    return;
  }
  double* xs = x.data();
  const auto relax = [&](int i) {  // x_i = D_i^-1 (b_i - sum_{j != i} A_ij x_j), the diagonal first
    double s0 = b(0, i), s1 = b(1, i), s2 = b(2, i);
    for (int e = A.start[i] + 1; e < A.start[i + 1]; ++e) {
      const double* m = A.value[e].data();  // column-major
      const double* v = xs + 3 * A.col[e];
      s0 -= m[0] * v[0] + m[3] * v[1] + m[6] * v[2];
      s1 -= m[1] * v[0] + m[4] * v[1] + m[7] * v[2];
      s2 -= m[2] * v[0] + m[5] * v[1] + m[8] * v[2];
    }
    const double* d = A.diag_inverse[i].data();
    double* out = xs + 3 * i;
    out[0] = d[0] * s0 + d[3] * s1 + d[6] * s2;
    out[1] = d[1] * s0 + d[4] * s1 + d[7] * s2;
    out[2] = d[2] * s0 + d[5] * s1 + d[8] * s2;
  };
  const bool polynomial = l == 0 && options_.fine == FineSmoother::Chebyshev;
  if (polynomial) chebyshev(x, b, true);
  else
    for (int i = 0; i < n; ++i) relax(i);  // forward Gauss-Seidel
  coarse_correct(l);
  // The adjoint smoothing: the same polynomial, or the backward sweep.
  if (polynomial) chebyshev(x, b, false);
  else
    for (int i = n - 1; i >= 0; --i) relax(i);  // backward Gauss-Seidel
}

// x_l += P x_{l+1}, x_{l+1} the coarser level's cycle on the restricted residual P^T (b - A x).
void MultigridPreconditioner::coarse_correct(int l) const {
  const BlockRows& A = op_[l];
  const int n = A.size();
  Eigen::Matrix3Xd& x = x_[l];
  if (l == 0 && options_.fine == FineSmoother::Chebyshev) fine_multiply(x, t_[l]);
  else A.multiply(x, t_[l]);
  t_[l] = b_[l] - t_[l];
  const GridTransfer& P = transfer_[l];
  const bool finest = l == 0;
  Eigen::Matrix3Xd& bc = b_[l + 1];
  bc.setZero(3, P.coarse_bodies);
  for (int i = 0; i < n; ++i) {
    if (finest && fixed_[i]) continue;
    for (int e = P.start[i]; e < P.start[i + 1]; ++e) bc.col(P.coarse[e]) += P.weight[e] * t_[l].col(i);
  }
  cycle(l + 1);
  const Eigen::Matrix3Xd& xc = x_[l + 1];
  for (int i = 0; i < n; ++i) {
    if (finest && fixed_[i]) continue;
    for (int e = P.start[i]; e < P.start[i + 1]; ++e) x.col(i) += P.weight[e] * xc.col(P.coarse[e]);
  }
}

void MultigridPreconditioner::apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const {
  b_[0] = r;
  cycle(0);
  z = x_[0];
  held_.apply(z);  // S z: held normals untouched
}

}  // namespace clothsim
