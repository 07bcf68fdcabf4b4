#pragma once
// Declared parameters: they drive GUI sliders, JSON validation and permutations.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace salsa {

struct Parameter {
  std::string name;
  double value = 0;  ///< default
  double min = 0;
  double max = 0;
  std::string unit;         ///< SI unit, or "" for a plain number
  std::string description;
  double step = 0;          ///< slider step; 1 makes an integer parameter; 0 means (max - min) / 100

  bool is_integer() const { return step == 1; }
  /// What is allowed, e.g. "[0, 10] m" or "whole number in [1, 64]".
  std::string range() const {
    return (is_integer() ? "whole number in [" : "[") + format(min) + ", " + format(max) + "]" +
           (unit.empty() ? "" : " " + unit);
  }
  /// Empty when `v` is allowed, else why not (e.g. "is out of range (allowed: [0, 10] m)").
  std::string check(double v) const {
    if (!std::isfinite(v) || v < min || v > max || (is_integer() && v != std::floor(v)))
      return "is out of range (allowed: " + range() + ")";
    return {};
  }
  /// The shortest text that reads back as exactly `v`, as messages show values: "10", "0.5",
  /// "0.016666666666666666", "1e-09"; plain digits from 1e-5 up to 1e17, an exponent beyond.
  static std::string format(double v) {
    const double size = std::fabs(v);
    const auto style = size == 0 || (size >= 1e-5 && size < 1e17) ? std::chars_format::fixed : std::chars_format::scientific;
    char text[64];
    return {text, std::to_chars(text, text + sizeof text, v, style).ptr};
  }
};

using Parameters = std::vector<Parameter>;

/// Current values by name. Small and flat: lookups are a few string compares.
class ParameterValues {
 public:
  ParameterValues() = default;
  /// The declared defaults.
  explicit ParameterValues(const Parameters& schema) {
    for (const auto& p : schema) values_.emplace_back(p.name, p.value);
  }
  bool has(std::string_view name) const { return find(name) != values_.end(); }
  double get(std::string_view name) const {
    auto it = find(name);
    if (it == values_.end()) throw std::out_of_range("unknown parameter '" + std::string(name) + "'");
    return it->second;
  }
  void set(std::string_view name, double value) {
    auto it = std::find_if(values_.begin(), values_.end(), [&](const auto& kv) { return kv.first == name; });
    if (it == values_.end()) values_.emplace_back(std::string(name), value);
    else it->second = value;
  }
  const std::vector<std::pair<std::string, double>>& items() const { return values_; }
  bool operator==(const ParameterValues&) const = default;

 private:
  std::vector<std::pair<std::string, double>>::const_iterator find(std::string_view name) const {
    return std::find_if(values_.begin(), values_.end(), [&](const auto& kv) { return kv.first == name; });
  }
  std::vector<std::pair<std::string, double>> values_;
};

/// Base of everything a plugin makes: holds its parameter values; `configure()` runs after they change
/// (cache them in members there when `decide` is hot).
class Configurable {
 public:
  virtual ~Configurable() = default;
  double param(std::string_view name) const { return values_.get(name); }
  const ParameterValues& parameters() const { return values_; }
  void set_parameters(ParameterValues values) {
    values_ = std::move(values);
    configure();
  }

 protected:
  virtual void configure() {}

 private:
  ParameterValues values_;
};

}  // namespace salsa
