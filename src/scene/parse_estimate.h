// What parsing a scene file will cost in memory, judged from its text before yaml-cpp reads it:
// yaml-cpp holds the whole node tree at once, about half a kilobyte a node, so a 7 MB file of
// keyframes takes most of a gigabyte (BENCHMARKS.md, "Memory estimate").
#pragma once

#include <cstdint>
#include <istream>

namespace clothsim {

// How many nodes (scalars, keys, collections) the YAML text will become, counted from its
// words without parsing it: never fewer than yaml-cpp builds for a text it accepts. Quoted
// strings are one node, comments none; a block sequence's dash or a key at the end of a line
// opens a nested collection, counted once.
struct YamlSize {
  std::int64_t nodes = 0;
  std::int64_t bytes = 0;
  std::int64_t long_scalar_bytes = 0;  // in scalars past std::string's inline 15 characters
};
YamlSize count_yaml_nodes(std::istream& text);

// Peak bytes of yaml-cpp's tree for such a text, beyond the process itself.
double parse_bytes(const YamlSize& size);

}  // namespace clothsim
