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

class Param;

/// Base of everything a plugin makes: holds its parameter values; `configure()` runs after they change.
/// A parameter is declared either once, as a `Param` member (below), or in `static Parameters declare()`
/// and read with `param("name")` (a lookup by name: cache it in `configure()` when `decide` is hot).
class Configurable {
 public:
  Configurable() = default;
  Configurable(const Configurable&) = delete;  // Param members point into the object
  Configurable& operator=(const Configurable&) = delete;
  virtual ~Configurable() = default;
  double param(std::string_view name) const { return values_.get(name); }
  const ParameterValues& parameters() const { return values_; }
  void set_parameters(ParameterValues values) {
    values_ = std::move(values);
    for (const auto& b : bound_)
      if (values_.has(b.declaration.name)) *b.value = values_.get(b.declaration.name);
    configure();
  }
  /// The declarations of the Param members, in member order.
  Parameters bound_parameters() const {
    Parameters out;
    for (const auto& b : bound_) out.push_back(b.declaration);
    return out;
  }

 protected:
  /// Runs after every change of values, Param members already set: derive state, or throw
  /// std::invalid_argument to refuse a combination of values (the message is shown with the plugin's name).
  virtual void configure() {}

 private:
  friend class Param;
  struct Binding {
    Parameter declaration;
    double* value;
  };
  ParameterValues values_;
  std::vector<Binding> bound_;
};

/// A parameter written once: the member is its declaration and holds its current value, so `decide`
/// reads a plain double (no lookup).
///   salsa::Param turn_interval{this, "turn_interval", 2.0, 0.1, 30.0, "s", "time between heading changes"};
class Param {
 public:
  Param(Configurable* owner, Parameter declaration) : value_(declaration.value) {
    owner->bound_.push_back({std::move(declaration), &value_});
  }
  Param(Configurable* owner, std::string name, double value, double min, double max, std::string unit = "",
        std::string description = "", double step = 0)
      : Param(owner, Parameter{std::move(name), value, min, max, std::move(unit), std::move(description), step}) {}
  Param(const Param&) = delete;
  Param& operator=(const Param&) = delete;
  operator double() const { return value_; }
  double value() const { return value_; }

 private:
  double value_;
};

}  // namespace salsa
