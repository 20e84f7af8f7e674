// The doors' text helpers (scene/text.h): the nearest name to a typo, and where a YAML bracket
// left open began.
#include "scene/text.h"

#include <gtest/gtest.h>

using namespace clothsim;

TEST(NearestName, FindsTheNameATypoMeantAndNothingForAWordFarFromAll) {
  EXPECT_EQ(nearest_name("stifness", {"stiffness", "damping"}), "stiffness");                      // a letter short
  EXPECT_EQ(nearest_name("comapre", {"run", "compare", "bench", "converge"}), "compare");          // two swapped
  EXPECT_EQ(nearest_name("kss", {"name", "dt", "cloth", "ks", "kd"}), "ks");                        // one more
  EXPECT_EQ(nearest_name("rows", {"i", "j"}), "");                                                  // nothing near
  EXPECT_EQ(nearest_name("xy", {"dt", "ks"}), "") << "two edits of two letters is any word";
}

TEST(UnclosedBracketLine, IsTheLineOfTheInnermostBracketStillOpen) {
  const std::string text = "a: 1\nb: [1, 2\nc: {x: [3]\n";
  EXPECT_EQ(unclosed_bracket_line(text, text.size()), 3);  // the '{' of line 3 ('[3]' closed)
  EXPECT_EQ(unclosed_bracket_line(text, text.find("c:")), 2);
  EXPECT_EQ(unclosed_bracket_line("a: [1]  # [not a bracket\nb: '[' \n", 30), 0) << "comments and quotes skipped";
  EXPECT_EQ(unclosed_bracket_line("a: [1]\n", 7), 0);
}
