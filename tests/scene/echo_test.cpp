// Echoed user text: one line, at most 80 characters, escapes for what a terminal would act on.
#include "scene/echo.h"

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

TEST(OneLine, EscapesRawControlBytesButNotTheEscapesOfAnEchoedValue) {
  // A message holding an echoed value: its newline is escaped once, by in_quotes(), and stays so.
  const std::string message = "unknown integrator " + in_quotes("a\nb");
  ASSERT_EQ(message, "unknown integrator 'a\\nb'");
  EXPECT_EQ(one_line(message), message);
  // What no echo went through (a library's message, a path) is made one line here.
  EXPECT_EQ(one_line("cannot write a\nb.csv:\tFile too large\x1b[31m"),
            "cannot write a\\nb.csv:\\tFile too large\\x1b[31m");
  EXPECT_EQ(one_line("C:\\dir"), "C:\\dir") << "a backslash in raw text is shown as it is";
}

TEST(OneLine, IsIdempotentAndCutsAsExcerptDoes) {
  const std::string raw = "x\n" + in_quotes("y\tz\\") + std::string(3000, 'w');
  EXPECT_EQ(one_line(one_line(raw)), one_line(raw));
  EXPECT_EQ(one_line(raw).size(), 2000u);
  EXPECT_EQ(one_line(raw).substr(1997), "...");
}

}  // namespace
}  // namespace clothsim
