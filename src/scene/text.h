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

}  // namespace clothsim
