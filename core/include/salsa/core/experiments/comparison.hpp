#pragma once
// The paired comparison of behaviors: tests that share a cell (everything but the behavior) and a seed
// are pairs, so the difference between two variants is measured on the same worlds. See
// docs/output-format.md (comparison.csv).
#include <filesystem>
#include <string>

namespace salsa {

/// Reads OUT/summary.csv and writes OUT/comparison.csv: for each cell and each pair of variants (A, B)
/// in it, in order of first appearance, the pairs' mean difference A − B of `metric` with its 95 %
/// t-interval and A's win rate. Throws InputError (one line naming the file) on bad input.
void write_comparison(const std::filesystem::path& out, const std::string& metric = "fraction_found");

/// Half the width of the two-sided 95 % t-interval of a mean of `n` values with sample standard
/// deviation `sd`: t_{0.975, n-1} · sd / √n. NaN for n < 2.
double t_half_width(std::size_t n, double sd);

}  // namespace salsa
