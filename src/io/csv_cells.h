// A CSV cell of a study's table, as every writer of one spells it (bench, stability, converge,
// merge, and the Python module's csv=): numbers in the shortest form that reads back exactly
// (nan stays "nan"), and text quoted when it holds a comma, a quote or a control byte (RFC
// 4180; control bytes become spaces), so no text can break a row.
#pragma once

#include <string>

namespace clothsim {

std::string csv_number(double value);
std::string csv_text(const std::string& text);

}  // namespace clothsim
