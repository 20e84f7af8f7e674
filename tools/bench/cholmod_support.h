// What the two CHOLMOD peer benchmarks share (cholmod_peer_bench.cpp, projective dynamics'
// matrix; cholmod_implicit_bench.cpp, implicit Euler's): CHOLMOD's view of an Eigen matrix's
// lower triangle, and its workspace started and finished around a benchmark.
#pragma once

#include <suitesparse/cholmod.h>

#include <Eigen/SparseCore>
#include <cstddef>

namespace clothsim::bench {

// CHOLMOD's view of `lower` (no copy): symmetric, the lower triangle stored, compressed.
inline cholmod_sparse cholmod_view(Eigen::SparseMatrix<double>& lower) {
  cholmod_sparse a{};
  a.nrow = a.ncol = static_cast<std::size_t>(lower.rows());
  a.nzmax = static_cast<std::size_t>(lower.nonZeros());
  a.p = lower.outerIndexPtr();
  a.i = lower.innerIndexPtr();
  a.x = lower.valuePtr();
  a.stype = -1;  // symmetric, lower triangle stored
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

// cholmod_common, started on construction and finished on destruction; each benchmark sets
// its own options on `c` (supernodal or simplicial, the ordering).
struct CholmodCommon {
  cholmod_common c{};
  CholmodCommon() { cholmod_start(&c); }
  ~CholmodCommon() { cholmod_finish(&c); }
  CholmodCommon(const CholmodCommon&) = delete;
  CholmodCommon& operator=(const CholmodCommon&) = delete;
};

}  // namespace clothsim::bench
