#pragma once
// How salsa writes numbers in messages and files that people read, in one place. (CSV fields have
// their fixed decimals in CsvWriter; JSON goes through nlohmann-json.)
#include <string>

#include "salsa/parameters.hpp"

namespace salsa::format {

/// The shortest text that reads back as exactly `v` ("10", "0.5", "1e-09"): values as a user typed them.
inline std::string number(double v) { return Parameter::format(v); }
/// A time in seconds as messages show it: 6 significant digits ("12.5", "1200", "0.0166667").
std::string seconds(double t);
/// `v` to `digits` significant digits ("1.2e+11", "0.35").
std::string significant(double v, int digits);
/// A count with thousands separators: 1234567 -> "1,234,567" (rounded to a whole number).
std::string grouped(double v);

}  // namespace salsa::format
