// The parse estimate counts at least the nodes yaml-cpp builds, whatever the YAML's style.
#include "scene/parse_estimate.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <sstream>
#include <string>

namespace clothsim {
namespace {

std::int64_t tree_nodes(const YAML::Node& node) {
  std::int64_t n = 1;
  if (node.IsSequence())
    for (const YAML::Node& item : node) n += tree_nodes(item);
  if (node.IsMap())
    for (const auto& pair : node) n += tree_nodes(pair.first) + tree_nodes(pair.second);
  return n;
}

std::int64_t counted(const std::string& text) {
  std::istringstream in(text);
  return count_yaml_nodes(in).nodes;
}

TEST(ParseEstimate, CountsAtLeastTheNodesYamlCppBuildsInEveryStyle) {
  const char* texts[] = {
      "a: 1\nb: [1, 2, 3]\n",
      "motion:\n  - {t: 1.0, velocity: [0, 0, 5]}\n  - {t: 2.0, velocity: [0, 0, 0]}\n",
      "motion:\n  - t: 1.0\n    velocity: [0, 0, 5]\n  - t: 2.0\n    velocity:\n      - 0\n      - 0\n      - 1\n",
      "junk:\n  k1:\n    s: 0\n  k2:\n    s: 0\n",
      "- - 0\n  - 1\n- - 2\n",
      "a: [[0], [1], [[2, 3]]]\n",
      "a: {b: {c: {d: 1}}}\n",
      "a:\nb:\n",
      "s: \"a # b, [c] {d}\"\nt: 'don''t, [stop]'\nu: [don't, 1, 2]\n",
      "# a comment: [1, 2, 3]\na: 1  # another, {x: 1}\n",
      "a: \"multi\n  line, [1, 2]\"\nb: [3, 4]\n",
  };
  for (const char* text : texts) EXPECT_GE(counted(text), tree_nodes(YAML::Load(text))) << text;
}

TEST(ParseEstimate, CountsAFlowListOfScalarsExactly) {
  std::string text = "junk: [";
  for (int i = 0; i < 1000; ++i) text += i ? ",0" : "0";
  text += "]\n";
  EXPECT_EQ(counted(text), tree_nodes(YAML::Load(text)));  // map, key, sequence, 1000 scalars
}

TEST(ParseEstimate, AQuotedStringIsOneNodeAndItsLengthIsCounted) {
  const std::string text = "name: \"" + std::string(1000, 'x') + " [1, 2] # no comment\"\n";
  std::istringstream in(text);
  const YamlSize size = count_yaml_nodes(in);
  EXPECT_EQ(size.nodes, 3);  // the map, its key and the string
  EXPECT_EQ(size.bytes, static_cast<std::int64_t>(text.size()));
  EXPECT_GT(size.long_scalar_bytes, 1000);
}

// 200,000 keyframes (7 MB of YAML) peaked at 1 222 MiB before parsing was counted: the
// estimate is of that order, about half a kilobyte a node (BENCHMARKS.md, "Memory estimate").
TEST(ParseEstimate, AKeyframeListCostsAboutHalfAKilobyteANode) {
  std::string text = "motion:\n";
  for (int i = 0; i < 1000; ++i) text += "  - {t: 1.000" + std::to_string(i) + ", velocity: [0, 0, 5]}\n";
  std::istringstream in(text);
  const YamlSize size = count_yaml_nodes(in);
  EXPECT_EQ(size.nodes, tree_nodes(YAML::Load(text)));  // 8 a keyframe, and the list and its key
  EXPECT_NEAR(parse_bytes(size) / static_cast<double>(size.nodes), 512 + 4.0 * text.size() / size.nodes, 1e-9);
}

}  // namespace
}  // namespace clothsim
