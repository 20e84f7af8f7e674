// One entry for every input a user can hand the scene front end: YAML text, `--set`
// overrides, validation and Model building. libFuzzer calls it through tools/fuzz (clang,
// ASan + UBSan); the ordinary suite calls it on every file in tests/fuzz/regressions/ (g++),
// so an input that ever failed is checked by every `tools/test.sh` from then on.
//
// Input format, so that any scene file is a valid input and the corpus stays readable: the
// whole text is the scene; each line starting with "#--set " (a YAML comment, ignored by
// the parser) is also one override, KEY=VALUE, with \n, \t, \\ and \xHH escapes so a value
// can hold a newline or any byte.
//
// What it holds the front end to, whatever the bytes:
// - the only exception is SceneError, and its message is one line, names the file, is at
//   most kMaxMessage bytes (values are echoed as 80-character excerpts);
// - a scene that validates has duration / dt and frames within run_bounds.h;
// - a scene within kFuzzMemory (what --max-memory would refuse, it refuses too) builds a
//   Model whose arrays have the declared shapes, spring and triangle indices in range, finite
//   initial positions, velocities and rest lengths, a timeline in order, as many springs as
//   memory_estimate.h counts, and no more bytes than model_bytes() estimates.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clothsim::fuzz {

inline constexpr std::size_t kMaxMessage = 600;        // bytes of one error message
inline constexpr double kFuzzMemory = 64.0 * 1024 * 1024;  // the estimate a fuzzed Model may reach

// The scene text and its overrides, as split from one input.
struct SceneInput {
  std::string text;
  std::vector<std::string> overrides;
};
SceneInput split_input(const std::uint8_t* data, std::size_t size);

// "" when the input was handled as the contract says (accepted, or refused with a good
// SceneError); otherwise what went wrong, in one line.
std::string scene_input_problem(const std::uint8_t* data, std::size_t size);

}  // namespace clothsim::fuzz
