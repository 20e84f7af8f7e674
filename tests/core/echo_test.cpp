// Echoed user text: one line, at most 80 characters, escapes for what a terminal would act on.
#include "echo.h"

#include <gtest/gtest.h>

#include <string>

namespace clothsim {
namespace {

TEST(Excerpt, KeepsShortPlainTextAsItIs) {
  EXPECT_EQ(excerpt("symplectic_euler"), "symplectic_euler");
  EXPECT_EQ(in_quotes("1e-4"), "'1e-4'");
  EXPECT_EQ(excerpt(""), "");
}

TEST(Excerpt, EscapesNewlinesTabsBackslashesAndControlBytes) {
  EXPECT_EQ(excerpt("a\nb\tc\r\\d\x1b[31m"), "a\\nb\\tc\\r\\\\d\\x1b[31m");
}

TEST(Excerpt, CutsLongTextToTheLimitEndingInDots) {
  const std::string cut = excerpt(std::string(1000, 'x'));
  EXPECT_EQ(cut.size(), 80u);
  EXPECT_EQ(cut.substr(77), "...");
  EXPECT_EQ(excerpt(std::string(80, 'y')), std::string(80, 'y')) << "exactly the limit: not cut";
  std::string escaped_newlines;
  for (int i = 0; i < 38; ++i) escaped_newlines += "\\n";
  EXPECT_EQ(excerpt(std::string(500, '\n')), escaped_newlines + "...")
      << "escapes count toward the limit, and 38 whole ones fit before the dots";
}

TEST(Excerpt, NeverSplitsAnEscapeOrAUtf8Character) {
  const std::string cut = excerpt(std::string(76, 'a') + "\n\n\n\n");
  EXPECT_EQ(cut, std::string(76, 'a') + "...") << "a \\n does not fit whole before the dots";
  // The limit counts bytes: a two-byte e-acute after 76 bytes would leave no room for the dots.
  const std::string accents = excerpt(std::string(75, 'a') + "\xc3\xa9\xc3\xa9\xc3\xa9");
  EXPECT_EQ(accents, std::string(75, 'a') + "\xc3\xa9...");
}

}  // namespace
}  // namespace clothsim
