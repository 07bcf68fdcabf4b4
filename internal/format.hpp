#pragma once
// How salsa writes numbers and points in messages and in files people read, in one place for every
// layer (the core, the built-in plugins, the CLI, the plots and the desktop). CSV fields have their
// fixed decimals in CsvWriter; JSON goes through nlohmann-json.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "salsa/parameters.hpp"
#include "salsa/vec2.hpp"

namespace salsa::format {

/// The shortest text that reads back as exactly `v` ("10", "0.5", "1e-09"): a value as the user typed
/// it, and every limit a user may type back.
inline std::string number(double v) { return Parameter::format(v); }

/// `v` to `digits` significant digits ("1.2e+11", "0.35").
inline std::string significant(double v, int digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

/// A measured or computed value in a message: whole numbers in full, others to 6 significant digits
/// ("12", "0.0166667", "nan", "inf").
inline std::string figure(double v) {
  char text[48];
  if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e15) std::snprintf(text, sizeof text, "%.0f", v);
  else std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// A figure derived for an explanation ("16.7 m per step"): 3 significant digits, no exponent from
/// 1,000 up.
inline std::string short_figure(double v) {
  char text[48];
  std::snprintf(text, sizeof text, std::abs(v) >= 1000 && std::abs(v) < 1e15 ? "%.0f" : "%.3g", v);
  return text;
}

/// A figure a message compares with a bound ("1.00002 m per step, more than its radius 1 m"):
/// short_figure's 3 significant digits, or as many more as it takes to read on the same side of
/// `bound` as `v` is, so that no value is ever rounded onto or past the limit it breaks.
inline std::string beyond(double v, double bound) {
  if (!std::isfinite(v) || !std::isfinite(bound) || v == bound) return short_figure(v);
  for (int digits = 3; digits < 17; ++digits) {
    std::string text = digits == 3 ? short_figure(v) : significant(v, digits);
    const double read = std::strtod(text.c_str(), nullptr);
    if ((read > bound) == (v > bound) && read != bound) return text;
  }
  return number(v);  // exact
}

/// A limit quoted to the user, rounded down to 4 significant digits so that the value they may type
/// back is within it.
inline std::string limit(double x) {
  const double scale = std::pow(10.0, std::floor(std::log10(x)) - 3);
  return figure(std::floor(x * (1 + 1e-9) / scale) * scale);
}

/// A time in seconds as messages show it: 6 significant digits ("12.5", "1200", "0.0166667").
inline std::string seconds(double t) { return significant(t, 6); }

/// A count with thousands separators: 1234567 -> "1,234,567" (rounded to a whole number).
inline std::string grouped(double v) {
  if (!std::isfinite(v)) return significant(v, 6);
  std::string digits = significant(std::round(std::fabs(v)), 30), out = v <= -0.5 ? "-" : "";
  if (digits.find_first_of("e.") != std::string::npos) return significant(v, 6);  // beyond 1e30: no grouping
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

/// A point as test and map files write it, "[x, y]", each coordinate as `number` writes it: the
/// point a user can find in their file.
inline std::string point(Vec2 p) {
  std::string s = "[";  // appended, not "[" + ...: GCC 12 -O3 warns (-Wrestrict) on that
  s += number(p.x);
  s += ", ";
  s += number(p.y);
  return s += ']';
}

/// A rectangle by its corners, as a map's bounds: "min [x, y], max [x, y]".
inline std::string rect(const Rect& r) { return "min " + point(r.min) + ", max " + point(r.max); }

}  // namespace salsa::format
