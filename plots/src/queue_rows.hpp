#pragma once
// A queue folder's tests as its plots group them (queue_rows.cpp).
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace salsa::plots {

struct QueueRow {
  std::string name, variant, drones, behavior, condition, condition_label;
  double size, found;  // drones as a number; found: %
  std::map<std::string, double> params;  // the behavior's parameters: summary.csv's behavior.<p>
};

/// Each condition's label (what it changes, in words), by the condition's name.
using ConditionLabels = std::map<std::string, std::string>;

/// OUT/summary.csv's ok tests as the plots group them, and their conditions' labels as comparison.csv
/// and did.csv name the conditions.
std::vector<QueueRow> read_queue_rows(const std::filesystem::path& out, ConditionLabels* labels);

/// The values of `key` in order of first appearance.
std::vector<std::string> in_order(const std::vector<QueueRow>& rows, std::string QueueRow::*key);
/// The swarm sizes, smallest first.
std::vector<std::string> sizes_of(const std::vector<QueueRow>& rows);
/// Variants as the plots show them: behaviors in order of first appearance, each one's defaults first,
/// then its other variants with numbers compared as numbers (alpha = 1 < 1.4 < 1.8 < 10).
std::vector<std::string> variants_of(const std::vector<QueueRow>& rows);
/// The conditions in order of first appearance ("" for a queue without conditions).
std::vector<std::string> conditions_of(const std::vector<QueueRow>& rows);

}  // namespace salsa::plots
