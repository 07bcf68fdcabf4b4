#pragma once
// The queue's comparison plots (comparison_plots.cpp), from comparison.csv and did.csv.
#include <filesystem>

#include "queue_rows.hpp"

namespace salsa::plots {

// comparison.png: one row per pair of variants in a cell and condition.
void forest(const std::filesystem::path& csv, const std::filesystem::path& file, const ConditionLabels& labels);
// did.png: one row per pair of variants and condition: (A − B | condition) − (A − B | baseline).
void did_plot(const std::filesystem::path& csv, const std::filesystem::path& file, const ConditionLabels& labels);

}  // namespace salsa::plots
