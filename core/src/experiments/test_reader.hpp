#pragma once
// Reading test and queue JSON with one-line errors, and what a test's reader, writer and setup share. Internal to libsalsa.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "strict_json.hpp"
#include "format.hpp"

namespace salsa::detail {

using json = nlohmann::ordered_json;

inline std::string show(const json& v) { return strict_json::shown(v); }

/// Reads JSON values with one-line errors: "<where>: <field>: <value> <what is allowed>".
class Reader {
 public:
  Reader(std::string where, std::filesystem::path base) : where_(std::move(where)), base_(std::move(base)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    // Names and keys quoted in `message` are user text: one line whatever they hold.
    throw InputError(where_ + ": " + field + ": " + strict_json::printable(message, 1000));
  }
  void only_keys(const json& obj, const std::string& field, std::initializer_list<const char*> allowed) const {
    only_keys(obj, field, std::vector<const char*>(allowed));
  }
  void only_keys(const json& obj, const std::string& field, const std::vector<const char*>& allowed) const {
    if (!obj.is_object()) fail(field.empty() ? "(top level)" : field, show(obj) + " must be an object");
    for (const auto& [key, value] : obj.items()) {
      bool ok = false;
      std::string list;
      for (const char* a : allowed) {
        ok = ok || key == a;
        list += (list.empty() ? "" : ", ") + std::string(a);
      }
      if (!ok) fail(join(field, key), "unknown key (allowed: " + list + ")");
    }
  }
  double number(const json& v, const std::string& field, double lo, double hi, const char* unit = "") const {
    const std::string range = "[" + format::number(lo) + ", " + format::number(hi) + "]" + (*unit ? std::string(" ") + unit : "");
    if (!v.is_number()) fail(field, show(v) + " is not a number (allowed: " + range + ")");
    const double x = v.get<double>();
    if (!(x >= lo && x <= hi)) fail(field, show(v) + " is out of range (allowed: " + range + ")");
    return x;
  }
  /// A whole number above `hi` that rounds onto it as a double (2^53 + 1 reads as 2^53): compared exactly.
  static bool past(const json& v, double hi) {
    return v.is_number_unsigned() && hi < 18446744073709551615.0 && v.get<std::uint64_t>() > static_cast<std::uint64_t>(hi);
  }
  std::uint64_t integer(const json& v, const std::string& field, double lo, double hi) const {
    const std::string range = "whole number in [" + format::number(lo) + ", " + format::number(hi) + "]";
    if (!v.is_number() || v.get<double>() != std::floor(v.get<double>()))
      fail(field, show(v) + " is not a whole number (allowed: " + range + ")");
    if (!(v.get<double>() >= lo && v.get<double>() <= hi) || past(v, hi)) fail(field, show(v) + " is out of range (allowed: " + range + ")");
    return v.is_number_unsigned() ? v.get<std::uint64_t>() : static_cast<std::uint64_t>(v.get<double>());
  }
  std::string string(const json& v, const std::string& field) const {
    if (!v.is_string() || v.get<std::string>().empty()) fail(field, show(v) + " must be a non-empty string");
    return v.get<std::string>();
  }
  /// A short name of the user's for a condition or a variant, shown in summary.csv and the plots: one
  /// line of at most max_label characters.
  static constexpr std::size_t max_label = 60;
  std::string label(const json& v, const std::string& field) const {
    const std::string allowed = " (allowed: text of 1 to " + std::to_string(max_label) + " characters on one line)";
    if (!v.is_string() || v.get<std::string>().empty()) fail(field, show(v) + " is not a label" + allowed);
    const std::string& s = v.get<std::string>();
    std::size_t characters = 0;
    for (unsigned char c : s) {
      if (c < 0x20 || c == 0x7f) fail(field, show(v) + " holds a control character" + allowed);
      characters += (c & 0xC0) != 0x80;  // UTF-8: count the first byte of each character
    }
    if (characters > max_label) fail(field, show(v) + " has " + std::to_string(characters) + " characters" + allowed);
    return s;
  }
  std::filesystem::path path(const json& v, const std::string& field) const {
    std::filesystem::path p = string(v, field);
    return p.is_relative() && !base_.empty() ? (base_ / p).lexically_normal() : p;
  }
  /// Validates given values against the declared parameters and fills in the defaults.
  ParameterValues params(const json& given, const std::string& field, const Parameters& schema,
                         const std::string& owner) const {
    ParameterValues values(schema);
    if (given.is_null()) return values;
    if (!given.is_object()) fail(field, show(given) + " must be an object of parameter values");
    for (const auto& item : given.items()) {
      const std::string& key = item.key();  // not a structured binding: clang 14 (fuzz preset) cannot capture those
      const json& v = item.value();
      auto it = std::find_if(schema.begin(), schema.end(), [&](const Parameter& p) { return p.name == key; });
      if (it == schema.end()) {
        std::string declared;
        for (const auto& p : schema) declared += (declared.empty() ? "" : ", ") + p.name;
        fail(join(field, key), "unknown parameter of " + owner + " (declared: " + (declared.empty() ? "none" : declared) + ")");
      }
      if (!v.is_number()) fail(join(field, key), show(v) + " is not a number (allowed: " + it->range() + ")");
      const std::string why = it->check(v.get<double>());
      if (!why.empty()) fail(join(field, key), show(v) + " " + why);
      values.set(key, v.get<double>());
    }
    return values;
  }
  static std::string join(const std::string& field, const std::string& key) {
    return (field.empty() ? "" : field + ".") + strict_json::printable(key);
  }

 private:
  std::string where_;
  std::filesystem::path base_;
};

/// The keys of a test object: its own, with the test models' sections after "groups" (test_models.hpp).
std::vector<const char*> test_keys();

/// Every JSON file salsa reads comes through here: strict (see strict_json.hpp), one line per problem.
json read_json_file(const std::filesystem::path& file, std::string_view expected);
/// A drone configuration at `at` ("drone" in a test, its name in a drone configuration file).
DroneConfig parse_drone(const json& v, const Reader& r, const std::vector<DroneConfig>& named, const std::string& at);
/// A test model's section (test_models.hpp): each field checked against its declared range, nested
/// objects by the dots of the fields' names.
void parse_model(TestSpec& t, const TestModel& m, const json& section, const Reader& r);
/// The built-in configurations, then those of a drone configuration file.
std::vector<DroneConfig> drone_configs_file(const std::filesystem::path& file);
/// One test object; a test without "seed" gets the paired seed of queue seed 1 (queue.hpp).
TestSpec parse_test(const json& j, const Reader& r, const PluginHost& host);
/// A contact handler's values over its declared defaults (a TestSpec made in code may give none): what
/// config.json records and the handler is made with (test_writer.cpp, test_setup.cpp).
ParameterValues handler_params(const PluginChoice& c, const PluginHost& host);

}  // namespace salsa::detail
