#include "cholesky_preconditioner.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace clothsim {

namespace {

// A factor whose solve streams more than this from L is costed by its bytes (estimate_costs):
// between the refined drape's 32 x 32 (5 MB, the multiply-adds' count within 1.4x of the
// clock) and 64 x 64 (31 MB, 2.2x), on this machine's 32 MiB L3 shared by both cores.
constexpr double kCachedFactorBytes = 16.0 * (1 << 20);

// AMD on the bodies' graph (one vertex per body, an edge per spring): the fill of a block
// factor is the fill of this graph's, so ordering bodies rather than coordinates costs a ninth
// and keeps each body's three coordinates together. Returns order[new] = old.
std::vector<int> fill_reducing_order(const SpringBlockMatrix& A) {
  const int B = A.num_bodies();
  std::vector<Eigen::Triplet<double, int>> edges;
  edges.reserve(B + 2 * A.a.size());
  for (int i = 0; i < B; ++i) edges.emplace_back(i, i, 1.0);
  for (std::size_t s = 0; s < A.a.size(); ++s) {
    edges.emplace_back(A.a[s], A.b[s], 1.0);
    edges.emplace_back(A.b[s], A.a[s], 1.0);
  }
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> graph(B, B);
  graph.setFromTriplets(edges.begin(), edges.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation;
  Eigen::AMDOrdering<int>()(graph, permutation);  // indices()[new] = old, as Eigen's Cholesky uses it
  return std::vector<int>(permutation.indices().data(), permutation.indices().data() + B);
}

// Every strictly upper pair of A is a block of L whatever the order (fill only adds): the
// distinct pairs, counted by a counting sort on the lower index of each spring (two springs
// on one pair are one block).
std::size_t distinct_pairs(const SpringBlockMatrix& A) {
  const int B = A.num_bodies();
  std::vector<int> start(B + 1, 0), other(A.a.size());
  for (std::size_t s = 0; s < A.a.size(); ++s) ++start[std::min(A.a[s], A.b[s]) + 1];
  for (int i = 0; i < B; ++i) start[i + 1] += start[i];
  std::vector<int> next(start.begin(), start.end() - 1);
  for (std::size_t s = 0; s < A.a.size(); ++s) other[next[std::min(A.a[s], A.b[s])]++] = std::max(A.a[s], A.b[s]);
  std::size_t pairs = 0;
  for (int i = 0; i < B; ++i) {
    std::sort(other.begin() + start[i], other.begin() + start[i + 1]);
    pairs += static_cast<std::size_t>(std::unique(other.begin() + start[i], other.begin() + start[i + 1]) -
                                      (other.begin() + start[i]));
  }
  return pairs;
}

}  // namespace

void CholeskyPreconditioner::analyse(const SpringBlockMatrix& A, std::size_t budget_bytes) {
  const int B = A.num_bodies();
  bodies_ = B;
  analysed_ = true;
  ready_ = false;
  // A factor that cannot fit the budget is known before any ordering: AMD, its triplets and
  // the pattern would cost gigabytes on a sheet of millions (BENCHMARKS.md).
  blocks_ = distinct_pairs(A);
  if (factor_bytes() > budget_bytes) {
    order_.clear();
    rank_.clear();
    column_start_.clear();
    factor_cost_ = solve_cost_ = std::numeric_limits<double>::infinity();
    return;
  }
  order_ = fill_reducing_order(A);
  rank_.assign(B, 0);
  for (int k = 0; k < B; ++k) rank_[order_[k]] = k;
  build_upper_pattern(A);
  const std::vector<int> count = count_columns(B);
  column_start_.assign(B + 1, 0);
  for (int j = 0; j < B; ++j) column_start_[j + 1] = column_start_[j] + count[j];
  blocks_ = static_cast<std::size_t>(column_start_[B]);
  // L's storage and the factorisation's scratch wait for the first factorisation: most runs
  // never factor, and on a 256 x 256 sheet they would be hundreds of MB.
  row_.clear();
  value_.clear();
  upper_.clear();
  diag_.clear();
  filter_.clear();
  estimate_costs(count, A.a.size(), A.refresh_single_copy != nullptr);
}

// The strictly upper blocks by column (new indices), one slot per body pair: two springs on
// one pair add into the same slot. Springs are sorted into their columns by counting, then
// each column by (row, spring).
void CholeskyPreconditioner::build_upper_pattern(const SpringBlockMatrix& A) {
  const int B = A.num_bodies();
  const std::size_t S = A.a.size();
  std::vector<int> column_first(B + 1, 0);
  for (std::size_t s = 0; s < S; ++s) ++column_first[std::max(rank_[A.a[s]], rank_[A.b[s]]) + 1];
  for (int k = 0; k < B; ++k) column_first[k + 1] += column_first[k];
  std::vector<std::pair<int, std::size_t>> column(S);  // (row, spring), column by column
  {
    std::vector<int> next(column_first.begin(), column_first.end() - 1);
    for (std::size_t s = 0; s < S; ++s) {
      const int i = rank_[A.a[s]], k = rank_[A.b[s]];
      column[next[std::max(i, k)]++] = {std::min(i, k), s};
    }
  }
  upper_start_.assign(B + 1, 0);
  upper_row_.clear();
  spring_slot_.assign(S, 0);
  spring_transposed_.assign(S, false);
  for (int k = 0; k < B; ++k) {
    const auto first = column.begin() + column_first[k], last = column.begin() + column_first[k + 1];
    std::sort(first, last);
    for (auto e = first; e != last; ++e) {
      const auto [row, s] = *e;
      if (e == first || row != (e - 1)->first) upper_row_.push_back(row);
      spring_slot_[s] = static_cast<int>(upper_row_.size()) - 1;
      // The slot holds A(row, k), row < k: A(b, a) = A(a, b)^T when a comes second.
      spring_transposed_[s] = rank_[A.a[s]] > rank_[A.b[s]];
    }
    upper_start_[k + 1] = static_cast<int>(upper_row_.size());
  }
}

// The elimination tree and L's column counts (Davis 2005, "Algorithm 849: a concise sparse
// Cholesky factorization package", ldl_symbolic): row k of L is the set of nodes reached
// from A's column k up the tree.
std::vector<int> CholeskyPreconditioner::count_columns(int B) {
  parent_.assign(B, -1);
  flag_.assign(B, -1);
  std::vector<int> count(B, 0);
  for (int k = 0; k < B; ++k) {
    flag_[k] = k;
    for (int p = upper_start_[k]; p < upper_start_[k + 1]; ++p) {
      for (int i = upper_row_[p]; flag_[i] != k; i = parent_[i]) {
        if (parent_[i] == -1) parent_[i] = k;
        ++count[i];
        flag_[i] = k;
      }
    }
  }
  return count;
}

// Costs in block-Jacobi iterations, counted in multiply-adds (how well the counts match the
// clock: BENCHMARKS.md). Factor: row k updates, for every block L(k, j), the blocks above it
// in column j, and forms L(k, j) and its share of D_k: sum_j c_j (c_j + 3) / 2 products of 27.
// Solve: two 3x3 mat-vecs per block of L and one per body (D^-1), 9 each. A solve whose L does
// not fit the cache streams it from memory twice (76 bytes a block), where the iteration
// streams about 48 bytes a spring and 150 a body (21 and 126 from the float copy of a large
// sheet's matrix, block_matrix.h): there the bytes set the cost (measured on the refined drape
// at 64-256, 1.4-3.5 times the multiply-adds' count; BENCHMARKS.md, CHOLMOD).
void CholeskyPreconditioner::estimate_costs(const std::vector<int>& count, std::size_t S, bool single) {
  const int B = static_cast<int>(count.size());
  const double iteration = 9.0 * (2.0 * B + 2.0 * static_cast<double>(S));
  double factor = 0.0;
  for (int j = 0; j < B; ++j) factor += 27.0 * count[j] * (count[j] + 3.0) / 2.0 + 27.0;
  factor_cost_ = factor / iteration;
  solve_cost_ = 9.0 * (2.0 * column_start_[B] + B) / iteration;
  const double streamed = 2.0 * 76.0 * column_start_[B];
  if (streamed > kCachedFactorBytes)
    solve_cost_ = std::max(solve_cost_, streamed / ((single ? 21.0 : 48.0) * static_cast<double>(S) +
                                                     (single ? 126.0 : 150.0) * B));
}

bool CholeskyPreconditioner::factorize(const SpringBlockMatrix& A, const VelocityFilter& filter) {
  allocate_scratch(A.num_bodies());
  load_filtered(A, filter);
  ready_ = factor_rows(A.num_bodies());
  return ready_;
}

// The first factorisation's scratch (analyse leaves it unallocated).
void CholeskyPreconditioner::allocate_scratch(int B) {
  if (upper_.size() == upper_row_.size() && diag_.size() == static_cast<std::size_t>(B)) return;
  upper_.assign(upper_row_.size(), Mat3::Zero());
  diag_.assign(B, Mat3::Zero());
  filter_.assign(B, Mat3::Identity());
  filtered_.assign(B, 0);
  d_inverse_.assign(static_cast<std::size_t>(kBlock) * B + kBlockSlack, 0.0);
  y_.assign(static_cast<std::size_t>(kPaddedBlock) * B, 0.0);
  pattern_.assign(B, 0);
  filled_.assign(B, 0);
}

// The matrix in the new order: S P S + (I - S), P on the free directions and the identity
// along a held normal. Only held bodies' blocks need the products (usually a few); a free
// pair's block is P's, symmetric, so it goes in as it is whichever end comes first.
void CholeskyPreconditioner::load_filtered(const SpringBlockMatrix& A, const VelocityFilter& filter) {
  const int B = A.num_bodies();
  for (std::size_t c = 0; c < filter.size(); ++c) {
    filter_[filter.body[c]] = Mat3::Identity() - filter.normal[c] * filter.normal[c].transpose();
    filtered_[filter.body[c]] = 1;
  }
  for (int k = 0; k < B; ++k) {
    const int i = order_[k];
    if (!filtered_[i]) {
      diag_[k] = A.diag_projected[i];
      continue;
    }
    const Mat3& F = filter_[i];
    diag_[k] = F * A.diag_projected[i] * F + (Mat3::Identity() - F);
  }
  std::fill(upper_.begin(), upper_.end(), Mat3::Zero());
  for (std::size_t s = 0; s < A.a.size(); ++s) {
    if (!filtered_[A.a[s]] && !filtered_[A.b[s]]) {
      upper_[spring_slot_[s]] += A.off_projected(s);
      continue;
    }
    const Mat3 block = filter_[A.a[s]] * A.off_projected(s) * filter_[A.b[s]];
    if (spring_transposed_[s]) upper_[spring_slot_[s]] += block.transpose();
    else upper_[spring_slot_[s]] += block;
  }
  for (std::size_t c = 0; c < filter.size(); ++c) {
    filter_[filter.body[c]].setIdentity();
    filtered_[filter.body[c]] = 0;
  }
}

// Up-looking L D L^T in blocks (Davis 2005's ldl_numeric with 3x3 entries). Row k: the
// blocks Y_i = A(i, k) - sum_j L(i, j) Z_j^T over the reach of column k, in topological
// order, give Z_i = Y_i^T = L(k, i) D_i, so L(k, i) = Y_i^T D_i^-1 and
// D_k = A(k, k) - sum_i L(k, i) Y_i (block_factor_kernels.h runs the products).
// False where a pivot block is not SPD (a non-finite matrix).
bool CholeskyPreconditioner::factor_rows(int B) {
  ready_ = false;
  const std::size_t blocks = static_cast<std::size_t>(column_start_[B]);
  if (row_.size() != blocks) {
    row_.assign(blocks, 0);
    value_.assign(kBlock * blocks + kBlockSlack, 0.0);
  }
  std::fill(flag_.begin(), flag_.end(), -1);
  std::fill(filled_.begin(), filled_.end(), 0);
  double d[kPaddedBlock];
  for (int k = 0; k < B; ++k) {
    const int top = scatter_column(k, B);
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) d[4 * c + r] = diag_[k](r, c);
      d[4 * c + 3] = 0.0;
    }
    factor_row(k, pattern_.data() + top, B - top, y_.data(), column_start_.data(),
               filled_.data(), row_.data(), value_.data(), d_inverse_.data(), d);
    Mat3 dk;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) dk(r, c) = d[4 * c + r];
    const Eigen::LLT<Mat3> pivot(dk);
    if (pivot.info() != Eigen::Success || !dk.allFinite()) {
      std::fill(y_.begin(), y_.end(), 0.0);  // the next factorisation starts from zeros
      return false;
    }
    Eigen::Map<Mat3>(d_inverse_.data() + kBlock * k) = pivot.solve(Mat3::Identity());
  }
  return true;
}

// Scatters column k's upper blocks into y (padded) and lists the reach of column k up the
// elimination tree in pattern_[top .. B), in topological order. Returns top.
int CholeskyPreconditioner::scatter_column(int k, int B) {
  int top = B;
  flag_[k] = k;
  for (int p = upper_start_[k]; p < upper_start_[k + 1]; ++p) {
    int i = upper_row_[p];
    double* yi = y_.data() + kPaddedBlock * i;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) yi[4 * c + r] = upper_[p](r, c);
    int length = 0;
    for (; flag_[i] != k; i = parent_[i]) {
      pattern_[length++] = i;
      flag_[i] = k;
    }
    while (length > 0) pattern_[--top] = pattern_[--length];
  }
  return top;
}

void CholeskyPreconditioner::apply(const Eigen::Matrix3Xd& r, Eigen::Matrix3Xd& z) const {
  const int B = static_cast<int>(order_.size());
  w_.resize(static_cast<std::size_t>(kPaddedVector) * B);
  z.resize(3, B);
  PaddedFactor f;
  f.bodies = B;
  f.column_start = column_start_.data();
  f.row = row_.data();
  f.value = value_.data();
  f.d_inverse = d_inverse_.data();
  factor_solve(f, order_.data(), r.data(), z.data(), w_.data());
}

}  // namespace clothsim
