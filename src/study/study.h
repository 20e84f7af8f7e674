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

// Polled between runs and before every step of a run (Ctrl-C in the CLI), and told how many
// of a study's runs are done, from whichever thread finished one (calls are serialised).
struct StudyHooks {
  std::function<bool()> stop;
  std::function<void(long done, long total)> progress;
};

}  // namespace clothsim::analysis
