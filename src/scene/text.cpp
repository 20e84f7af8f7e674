#include "text.h"

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace clothsim {

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::optional<double> parse_number_or_fraction(const std::string& text) {
  const auto number = [](const std::string& s) -> std::optional<double> {
    if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (*end != '\0' || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    return v;
  };
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) return number(text);
  const auto num = number(text.substr(0, slash)), den = number(text.substr(slash + 1));
  if (!num || !den || *den == 0.0 || !std::isfinite(*num / *den)) return std::nullopt;
  return *num / *den;
}

std::vector<std::string> split_list(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!text.empty() && text.back() == sep) out.emplace_back();
  return out;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

std::string nearest_name(const std::string& typed, const std::vector<std::string>& names) {
  // The optimal string alignment distance: three rows of the dynamic programme.
  const auto distance = [](const std::string& a, const std::string& b) {
    std::vector<std::size_t> before(b.size() + 1), prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) cur[j] = std::min(cur[j], before[j - 2] + 1);
      }
      before.swap(prev);
      prev.swap(cur);
    }
    return prev[b.size()];
  };
  std::string best;
  std::size_t best_distance = 3;
  for (const std::string& name : names) {
    const std::size_t d = distance(typed, name);
    if (d < best_distance && 2 * d < typed.size()) {
      best = name;
      best_distance = d;
    }
  }
  return best;
}

int unclosed_bracket_line(const std::string& text, std::size_t until) {
  std::vector<int> open;  // the line of each bracket not yet closed
  int line = 1;
  char quote = 0;
  bool comment = false;
  for (std::size_t i = 0; i < std::min(until, text.size()); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      comment = false;
      if (quote == '\'') quote = 0;  // (a quote left open is yaml-cpp's own error to name)
      continue;
    }
    if (comment) continue;
    if (quote) {
      if (c == quote && (quote == '\'' || text[i - 1] != '\\')) quote = 0;
      continue;
    }
    if (c == '#' && (i == 0 || text[i - 1] == ' ' || text[i - 1] == '\t' || text[i - 1] == '\n')) comment = true;
    else if (c == '"' || c == '\'') quote = c;
    else if (c == '[' || c == '{') open.push_back(line);
    else if ((c == ']' || c == '}') && !open.empty()) open.pop_back();
  }
  return open.empty() ? 0 : open.back();
}

}  // namespace clothsim
