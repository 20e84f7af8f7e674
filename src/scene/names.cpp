#include "names.h"

#include <cstdio>

namespace clothsim {

char32_t bidi_control_at(std::string_view text, std::size_t i) {
  // U+202A-202E: E2 80 AA-AE; U+2066-2069: E2 81 A6-A9.
  if (i + 2 >= text.size() || static_cast<unsigned char>(text[i]) != 0xe2) return 0;
  const auto b1 = static_cast<unsigned char>(text[i + 1]), b2 = static_cast<unsigned char>(text[i + 2]);
  if (b1 == 0x80 && b2 >= 0xaa && b2 <= 0xae) return 0x2000 + (b2 - 0x80);
  if (b1 == 0x81 && b2 >= 0xa6 && b2 <= 0xa9) return 0x2040 + (b2 - 0x80);
  return 0;
}

std::string name_problem(std::string_view name) {
  if (name.empty()) return "is empty";
  if (name == "." || name == "..") return "is '" + std::string(name) + "', not a name";
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    char text[64];
    if (c == 0) return "holds a NUL byte (a name is text, and a NUL would cut a file name short)";
    if (c == '/' || c == '\\') return std::string("holds a path separator '") + name[i] + "' (a name, not a path)";
    if (c < 0x20 || c == 0x7f) {
      std::snprintf(text, sizeof text, "holds a control character (\\x%02x)", c);
      return text;
    }
    if (c == 0xc2 && i + 1 < name.size() && static_cast<unsigned char>(name[i + 1]) <= 0x9f &&
        static_cast<unsigned char>(name[i + 1]) >= 0x80) {  // U+0080-009F in UTF-8: C2 80-9F
      std::snprintf(text, sizeof text, "holds the C1 control character U+%04X",
                    static_cast<unsigned>(static_cast<unsigned char>(name[i + 1])));
      return text;
    }
    if (const char32_t bidi = bidi_control_at(name, i)) {
      std::snprintf(text, sizeof text, "holds the bidi control U+%04X", static_cast<unsigned>(bidi));
      return text;
    }
  }
  return "";
}

}  // namespace clothsim
