#include "echo.h"

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

// excerpt() and one_line(): `text` escaped, cut to `max` bytes.
std::string escaped(std::string_view text, std::size_t max, bool backslashes) {
  const std::size_t room = max > 3 ? max - 3 : 0;  // for the "..." of a cut
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    // One character: an escaped byte, or a whole UTF-8 sequence (lead byte + continuations).
    std::string piece = escape(static_cast<unsigned char>(text[i]), backslashes);
    std::size_t next = i + 1;
    if (static_cast<unsigned char>(text[i]) >= 0xc0)
      while (next < text.size() && (static_cast<unsigned char>(text[next]) & 0xc0) == 0x80)
        piece += text[next++];
    // Does the rest fit whole? Then no "..." is needed, so the last 3 places are usable too.
    if (out.size() + piece.size() > room) {
      std::string rest = out;
      for (std::size_t j = i; j < text.size() && rest.size() <= max; ++j)
        rest += escape(static_cast<unsigned char>(text[j]), backslashes);
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
