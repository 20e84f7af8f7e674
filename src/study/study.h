// What the studies (work precision, stability) share: the error they throw, and the hooks
// a caller steers them with.
//
// StudyError: a request a study cannot carry out as asked: an empty or non-positive step
// list, a step that does not divide the duration, a parameter that is not a number. The message is one sentence for the user; the CLI
// prefixes the option it came from and exits 2.
#pragma once

#include <functional>
#include <stdexcept>

namespace clothsim::analysis {

struct StudyError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// How far a study is: its runs (searches, sweeps) done of the total, and the share of its
// planned work they make where the study weighs its runs (work_precision: each by its
// cost_estimate, steps x force evaluations from its registry row). A study run dearest first
// finishes its largest run first, so a time-left estimate by count says 245 s left for a
// 15.7 s bench; by share it scales the time so far by what that run was worth.
struct StudyProgress {
  long done = 0, total = 0;
  double work_done = 0.0, work_total = 0.0;  // cost weights; work_total 0: every run weighs alike
  double share() const {  // of the study done, 0 to 1
    if (work_total > 0.0) return work_done / work_total;
    return total > 0 ? static_cast<double>(done) / static_cast<double>(total) : 0.0;
  }
};

// Polled between runs and before every step of a run (Ctrl-C in the CLI), and told how far the
// study is each time a run finishes, from whichever thread finished it (calls are serialised).
struct StudyHooks {
  std::function<bool()> stop;
  std::function<void(const StudyProgress& progress)> progress;
};

}  // namespace clothsim::analysis
