#pragma once
// The queue's comparison plots (comparison_plots.cpp), from comparison.csv and did.csv.
#include <QString>

#include <filesystem>

#include "queue_rows.hpp"

namespace salsa::plots {

// The queue's warnings as one line (OUT/comparison_notes.txt), "" when there are none.
QString comparison_note(const std::filesystem::path& out);
// comparison.png: one row per pair of variants in a cell and condition.
// `note` (the queue's warnings, "" for none) is drawn across the top of each.
void forest(const std::filesystem::path& csv, const std::filesystem::path& file, const ConditionLabels& labels, const QString& note = {});
// did.png: one row per pair of variants and condition: (A − B | condition) − (A − B | baseline).
void did_plot(const std::filesystem::path& csv, const std::filesystem::path& file, const ConditionLabels& labels, const QString& note = {});

}  // namespace salsa::plots
