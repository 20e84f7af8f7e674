#include "first_guess.h"

#include <cstddef>

#include "newton_kernels.h"

namespace clothsim {

DvHistory::DvHistory(const State& state, int B) {
  for (const Eigen::Matrix3Xd* m : {&state.implicit.dv, &state.implicit.dv_before, &state.implicit.dv_before2}) {
    if (m->cols() != B) break;
    dv[count++] = m;
  }
}

void guess_through(const DvHistory& past, int order, Eigen::Matrix3Xd& out) {
  if (order == 1) out.noalias() = 2.0 * *past.dv[0] - *past.dv[1];
  else out.noalias() = 3.0 * (*past.dv[0] - *past.dv[1]) + *past.dv[2];
}

int next_guess_order(const DvHistory& past, const Eigen::Matrix3Xd& dv) {
  if (past.count == 0) return 0;
  // Every order's distance in one pass (newton_kernels.h).
  double miss[kMaxGuessOrder + 1] = {0.0, 0.0, 0.0};
  simd_guess_misses(dv.data(), past.dv[0]->data(), past.count > 1 ? past.dv[1]->data() : nullptr,
                    past.count > 2 ? past.dv[2]->data() : nullptr, static_cast<std::size_t>(dv.size()), miss);
  int order = 0;
  for (int o = 1; o < past.count; ++o)
    if (kGuessAdvantage * kGuessAdvantage * miss[o] < miss[0] && miss[o] < miss[order]) order = o;
  return order;
}

}  // namespace clothsim
