// Names are names: a scene's `name` and a golden entry's `name` become file names (golden
// images, default output names), CSV cells and JSON strings. A NUL cuts a C path short (so
// "manifest.yaml\0" wrote over the manifest), a '/' leaves the folder, a control character
// or a bidi override corrupts a terminal or hides what a listing shows. They are refused at
// the key that holds them, with the parser's one-line error (file:line: key: ...).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace clothsim {

// "" when `name` may be used as a file name and a field; otherwise what is wrong, for the
// caller's one-line error: "holds a NUL byte", "holds a path separator '/'", "holds a control
// character (\x1b)", "holds the C1 control character U+0085", "holds the bidi control U+202E",
// "is empty", "is '.' or '..'".
std::string name_problem(std::string_view name);

// The Unicode bidi embedding, override and isolate controls (U+202A-202E, U+2066-2069): the
// code point of the one encoded in UTF-8 at text[i], or 0. echo.h's excerpt() shows them
// escaped (\u202e), so an echoed value reads in the order it is stored.
char32_t bidi_control_at(std::string_view text, std::size_t i);

}  // namespace clothsim
