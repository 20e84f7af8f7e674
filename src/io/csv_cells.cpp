#include "io/csv_cells.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace clothsim {

std::string csv_number(double value) {
  if (std::isnan(value)) return "nan";
  // The shortest of %.15g, %.16g, %.17g that reads back to the same double: 0.005 stays
  // "0.005", and no value loses a bit.
  char buf[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  return buf;
}

std::string csv_text(const std::string& text) {
  const auto control = [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; };
  if (text.find_first_of(",\"") == std::string::npos && std::none_of(text.begin(), text.end(), control)) return text;
  // Quoted (RFC 4180), and a control byte (a newline, CR, ESC, NUL) made a space: a cell is
  // one line of text in any reader, and a terminal showing the file obeys nothing in it.
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, control(c) ? ' ' : c);
  return quoted + "\"";
}

}  // namespace clothsim
