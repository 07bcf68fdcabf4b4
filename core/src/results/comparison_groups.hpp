#pragma once
// What comparison.cpp and ranking.cpp share: the ok tests of summary.csv grouped by cell and condition,
// and how their numbers are written. Internal to libsalsa.
#include <charconv>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace salsa::detail {

/// Six significant digits, whatever the locale: the files are compared byte for byte ("" for NaN).
inline std::string number(double v) {
  if (std::isnan(v)) return "";
  if (v == 0) v = 0;  // no "-0"
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr;
  return {buf, end};
}

/// The columns of summary.csv that describe a cell, copied into each row of the queue's tables.
inline constexpr const char* description[] = {"drones", "targets", "target", "map", "time"};

using Values = std::map<std::string, double>;  // "repeat/seed" → the metric

/// The ok tests of one cell under one condition.
struct Group {
  std::string cell, condition;
  std::vector<std::string> description;
  std::vector<std::string> variants;     // in order of first appearance
  std::map<std::string, Values> values;  // variant → its tests
};

/// The mean of each variant's values (in `g.variants`' order): what "top" and the ranking rank by.
inline std::vector<double> variant_means(const Group& g) {
  std::vector<double> out;
  for (const std::string& v : g.variants) {
    double sum = 0;
    for (const auto& [key, x] : g.values.at(v)) sum += x;
    out.push_back(sum / static_cast<double>(g.values.at(v).size()));
  }
  return out;
}

/// OUT/ranking.csv's text (docs/output-format.md#rankingcsv): each group's variants by rank.
std::string ranking_csv(const std::vector<Group>& groups, const std::string& metric);

}  // namespace salsa::detail
