// Names are names: what a scene or a golden entry calls itself can become a file name and a
// CSV or JSON field, so a NUL, a path separator, a control character or a bidi control is
// refused with the parser's one-line error; echoed text shows bidi controls escaped.
#include "scene/names.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "scene/echo.h"
#include "scene/scene_parser.h"

namespace clothsim {
namespace {

using namespace std::string_literals;

TEST(NameProblem, AcceptsPlainAndUnicodeNames) {
  for (const char* name : {"drape", "drape_rk4-2", "tissu à 45°", "布", "a.b"})
    EXPECT_EQ(name_problem(name), "") << name;
}

TEST(NameProblem, RefusesWhatWouldLeaveTheFolderOrCorruptAField) {
  EXPECT_NE(name_problem("manifest.yaml\0"s).find("NUL"), std::string::npos);
  EXPECT_NE(name_problem("../x").find("path separator '/'"), std::string::npos);
  EXPECT_NE(name_problem("a\\b").find("path separator"), std::string::npos);
  EXPECT_NE(name_problem("a\rb").find("control character (\\x0d)"), std::string::npos);
  EXPECT_NE(name_problem("\x1b[31mred").find("control character (\\x1b)"), std::string::npos);
  EXPECT_NE(name_problem("evil\u202Egnp.exe").find("bidi control U+202E"), std::string::npos);
  EXPECT_NE(name_problem("x\u2066y").find("U+2066"), std::string::npos);
  EXPECT_EQ(name_problem(""), "is empty");
  EXPECT_NE(name_problem("..").find("not a name"), std::string::npos);
}

TEST(NameProblem, RefusesEveryC1ControlAndKeepsTheLettersBesideThem) {
  // U+0080-009F (C2 80-9F in UTF-8): U+009B is a terminal's CSI, U+0085 a line break.
  for (unsigned c = 0x80; c <= 0x9f; ++c) {
    const std::string name = "a"s + static_cast<char>(0xc2) + static_cast<char>(c) + "b";
    char expected[48];
    std::snprintf(expected, sizeof expected, "C1 control character U+%04X", c);
    EXPECT_NE(name_problem(name).find(expected), std::string::npos) << c;
  }
  for (const char* name : {"\u00A0nbsp", "\u00A9 2026", "\u00E9t\u00E9"}) EXPECT_EQ(name_problem(name), "") << name;
}

TEST(BidiControl, FindsEveryEmbeddingOverrideAndIsolateAndNothingElse) {
  for (char32_t c : {0x202A, 0x202B, 0x202C, 0x202D, 0x202E, 0x2066, 0x2067, 0x2068, 0x2069}) {
    const std::string utf8 = {static_cast<char>(0xe0 | (c >> 12)), static_cast<char>(0x80 | ((c >> 6) & 0x3f)),
                              static_cast<char>(0x80 | (c & 0x3f))};
    EXPECT_EQ(bidi_control_at(utf8, 0), c);
  }
  EXPECT_EQ(bidi_control_at("\u2029", 0), 0u) << "a paragraph separator is not a bidi control";
  EXPECT_EQ(bidi_control_at("\u2065", 0), 0u);
  EXPECT_EQ(bidi_control_at("\xe2\x80", 0), 0u) << "cut short";
}

TEST(Excerpt, ShowsBidiControlsEscapedSoTextReadsAsStored) {
  EXPECT_EQ(excerpt("evil\u202Egnp.exe"), "evil\\u202egnp.exe");
  EXPECT_EQ(one_line("x \u2067y\u2069"), "x \\u2067y\\u2069");
  EXPECT_EQ(excerpt(std::string(100, 'a') + "\u202E").find('\xe2'), std::string::npos) << "nor in a cut";
}

TEST(SceneName, AHostileNameIsRefusedWithFileLineAndKey) {
  for (const char* name : {"\"a\\0b\"", "\"a/b\"", "\"a\\rb\"", "\"\\e[2J\"", "\"x\\u202Ey\""}) {
    try {
      parse_scene(std::string("duration: 1\nname: ") + name + "\n", "s.yaml");
      FAIL() << name;
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("s.yaml:2: name: ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace clothsim
