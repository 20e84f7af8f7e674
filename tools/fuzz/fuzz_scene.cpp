// libFuzzer's entry: every input through the scene front end (tests/fuzz/scene_fuzz.h); a
// broken contract is reported and aborts, so libFuzzer keeps the input as a crash.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz/scene_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = clothsim::fuzz::scene_input_problem(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "scene_fuzzer: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
