// Text as the doors read and write it: a scene's keys, the command line's options and the
// Python module's arguments all take numbers, fractions and lists the same way, so a value that
// one accepts the others accept too.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace clothsim {

// A number for a message as a user writes it: %g with 6 digits ("0.6", not "0.600000").
std::string number_text(double value);

// A finite number written as a number ("0.004", "4e-3") or a fraction of two ("1/60", the
// way a step of one per frame is said); nullopt for anything else (words, "1/0", "1/", "",
// and a space inside: "1/ 60").
std::optional<double> parse_number_or_fraction(const std::string& text);

// Splits "a,b,c" (empty pieces are an error reported by the caller).
std::vector<std::string> split_list(const std::string& text, char sep = ',');

// `s` without the spaces and tabs around it.
std::string trimmed(const std::string& s);

// The 1-based line of the innermost '[' or '{' still open at byte `until` of YAML `text`
// (quoted text and comments skipped), or 0: where an unclosed flow list or map began, which
// yaml-cpp reports only where it gave up looking for its end (the line after, or the end).
int unclosed_bracket_line(const std::string& text, std::size_t until);

// The one of `names` a typo of `typed` most likely meant: the nearest by edit distance
// (insertions, deletions, substitutions and swaps of neighbours, Damerau-Levenshtein), if it is
// at most 2 edits away and fewer than half of typed's letters; "" for none ("stifness" ->
// "stiffness", "comapre" -> "compare", "kss" -> "ks").
std::string nearest_name(const std::string& typed, const std::vector<std::string>& names);

}  // namespace clothsim
