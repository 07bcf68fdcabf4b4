#pragma once
// The queue's ranking plots (ranking_plots.cpp), from ranking.csv.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "queue_rows.hpp"

namespace salsa::plots {

/// The one number the conditions of OUT/summary.csv differ in: exactly one input column (the
/// behavior's aside) is the same within each condition and differs between them, and it is a number
/// in each ("comm.range": r50 → 50, r100 → 100). nullopt for fewer than two conditions, none, several,
/// or one that is not a number in every condition.
struct ConditionNumber {
  std::string key;
  std::map<std::string, double> values;  // condition → its value
};
std::optional<ConditionNumber> condition_number(const std::filesystem::path& out);

/// OUT/plots/ranking.png, and OUT/plots/by_<key>.png when the conditions differ in one number;
/// `variants` in plot order give the colours.
void ranking_plots(const std::filesystem::path& out, const std::vector<std::string>& variants, const ConditionLabels& labels);

}  // namespace salsa::plots
