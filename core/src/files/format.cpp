#include "salsa/core/files/format.hpp"

#include <cmath>
#include <cstdio>

namespace salsa::format {

std::string seconds(double t) { return significant(t, 6); }

std::string significant(double v, int digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

std::string grouped(double v) {
  if (!std::isfinite(v)) return significant(v, 6);
  std::string digits = significant(std::round(std::fabs(v)), 30), out = v <= -0.5 ? "-" : "";
  if (digits.find_first_of("e.") != std::string::npos) return significant(v, 6);  // beyond 1e30: no grouping
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace salsa::format
