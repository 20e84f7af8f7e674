// How a user's text is echoed in an error message: one line, at most 80 characters, control
// characters escaped. A scene value may be a megabyte long or hold newlines (a YAML block
// scalar); echoed raw, one bad value would bury the terminal and break the "one line per
// error" rule that scripts parsing stderr rely on.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace clothsim {

// `text` with \n, \r, \t, \\ and other control bytes escaped (\x1b), cut to at most `max`
// bytes ending in "..." when longer. Never cuts an escape or a UTF-8 character in two.
std::string excerpt(std::string_view text, std::size_t max = 80);

// excerpt() in single quotes (not `quoted`: std::quoted would win by argument lookup): 'value'.
std::string in_quotes(std::string_view text, std::size_t max = 80);

// A whole message made one line before it reaches the terminal (main's last guard): the
// control bytes still raw in it escaped as excerpt() escapes them, cut to `max` bytes as
// excerpt() cuts. Backslashes are left as they are: the message holds values already
// echoed through excerpt(), whose escapes ('a\nb' for a newline) must not be escaped a second
// time ('a\\nb'), so each value is escaped once, where it is echoed, and only text that no
// echo went through (a library's message, CLI11's, a path) is escaped here.
// one_line(one_line(m)) == one_line(m).
std::string one_line(std::string_view message, std::size_t max = 2000);

}  // namespace clothsim
