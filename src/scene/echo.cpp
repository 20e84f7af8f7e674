#include "echo.h"

#include <cstdio>

#include "names.h"

namespace clothsim {

namespace {

// The escaped form of one byte ("" for a UTF-8 continuation byte, kept with its lead); a
// backslash is doubled only when `backslashes` (not in one_line(): it is an escape already).
std::string escape(unsigned char c, bool backslashes) {
  switch (c) {
    case '\n': return "\\n";
    case '\r': return "\\r";
    case '\t': return "\\t";
    case '\\': return backslashes ? "\\\\" : "\\";
    default: break;
  }
  if (c < 0x20 || c == 0x7f) {
    const char* hex = "0123456789abcdef";
    return std::string("\\x") + hex[c >> 4] + hex[c & 15];
  }
  return std::string(1, static_cast<char>(c));
}

// One character at text[i], escaped: a byte, a bidi control shown as \u202e (not obeyed, so
// the text reads in the order it is stored), or a whole UTF-8 sequence. `next`: where the
// next character starts.
std::string piece_at(std::string_view text, std::size_t i, bool backslashes, std::size_t& next) {
  next = i + 1;
  if (const char32_t bidi = bidi_control_at(text, i)) {
    char code[16];
    std::snprintf(code, sizeof code, "\\u%04x", static_cast<unsigned>(bidi));
    next = i + 3;
    return code;
  }
  std::string piece = escape(static_cast<unsigned char>(text[i]), backslashes);
  if (static_cast<unsigned char>(text[i]) >= 0xc0)
    while (next < text.size() && (static_cast<unsigned char>(text[next]) & 0xc0) == 0x80) piece += text[next++];
  return piece;
}

// excerpt() and one_line(): `text` escaped, cut to `max` bytes.
std::string escaped(std::string_view text, std::size_t max, bool backslashes) {
  const std::size_t room = max > 3 ? max - 3 : 0;  // for the "..." of a cut
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t next = i;
    const std::string piece = piece_at(text, i, backslashes, next);
    // Does the rest fit whole? Then no "..." is needed, so the last 3 places are usable too.
    if (out.size() + piece.size() > room) {
      std::string rest = out;
      for (std::size_t j = i; j < text.size() && rest.size() <= max;) rest += piece_at(text, j, backslashes, j);
      if (rest.size() <= max) return rest;
      return out + "...";
    }
    out += piece;
    i = next;
  }
  return out;
}

}  // namespace

std::string excerpt(std::string_view text, std::size_t max) { return escaped(text, max, true); }

std::string one_line(std::string_view message, std::size_t max) { return escaped(message, max, false); }

std::string in_quotes(std::string_view text, std::size_t max) { return "'" + excerpt(text, max) + "'"; }

}  // namespace clothsim
