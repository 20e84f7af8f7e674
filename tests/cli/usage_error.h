// The message of the UsageError `f` throws, or "" when it throws none: for tests of the
// option parsers, which must reject bad input with a one-line message naming the option.
#pragma once

#include <functional>
#include <string>

#include "clip/common/cli_common.h"

namespace clothsim::testing {

inline std::string usage_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const clip::UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace clothsim::testing
