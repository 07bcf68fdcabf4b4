#pragma once
// The paired comparison of behaviors: tests that share a cell (everything but the behavior and the
// condition), a condition and a seed are pairs, so the difference between two variants is measured on
// the same worlds; the difference-in-differences between conditions; and each variant under each
// condition against itself under the first. See docs/output-format.md
// (comparison.csv, did.csv, condition_effects.csv, ranking.csv).
#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace salsa {

/// Reads OUT/summary.csv and writes OUT/comparison.csv: for each cell and condition and each pair of
/// variants (A, B) compared in it (compared_pairs), in order of first appearance, the pairs' mean
/// difference A − B of `metric` with its 95 % t-interval and A's win rate. When a cell has two or more
/// conditions, also OUT/did.csv: for each pair, (A − B | condition) − (A − B | the cell's first
/// condition), paired by repeat and seed (by repeat when the condition changes the world), with its
/// 95 % t-interval over the per-repeat values; and OUT/condition_effects.csv: for each variant,
/// (variant | condition) − (variant | the cell's first condition), paired the same way, with its 95 %
/// t-interval and the first condition's mean with its own. The reference and top are OUT/queue.json's,
/// or `pairing`'s when given (salsa plot OUT --reference / --top: queue.json is left as it is). Also
/// OUT/ranking.csv: within each cell and condition, each variant's mean with its 95 % t-interval, its
/// rank, the share of the repeats in which it is best and its paired difference from the best.
/// Without OUT/queue.json (test folders copied elsewhere), returns what it took from the folders' order
/// instead: the baseline condition and the pairs, in words ("" when there was no choice to make).
/// Throws InputError (one line naming the file) on bad input.
/// Which pairs comparison.csv and did.csv show: each variant against `reference`, or every pair of the
/// `top` best (a queue's "reference" and "top"; "" and 0: none).
struct Pairing {
  std::string reference;
  std::size_t top = 0;
};
std::string write_comparison(const std::filesystem::path& out, const std::string& metric = "fraction_found",
                             const std::optional<Pairing>& pairing = std::nullopt);

/// The variants of OUT/summary.csv's tests (any status), in order of first appearance: what a
/// reference or top given for OUT may name or count. Throws InputError (one line naming the file).
std::vector<std::string> queue_variants(const std::filesystem::path& out);

/// Half the width of the two-sided 95 % t-interval of a mean of `n` values with sample standard
/// deviation `sd`: t_{0.975, n-1} · sd / √n. NaN for n < 2.
double t_half_width(std::size_t n, double sd);

/// A paired comparison of two sets of values by key (NaN where undefined: means for n = 0, the
/// interval for n < 2).
struct PairedStats {
  std::size_t n;      ///< keys both have
  double mean_a, mean_b, mean_diff, ci_low, ci_high, win_rate_a;
};
PairedStats paired_stats(const std::map<std::string, double>& a, const std::map<std::string, double>& b);

/// A cell with more variants than this compares each against one (the first, without a reference).
inline constexpr std::size_t max_all_pairs = 4;
/// The pairs (A, B) of `variants` (indices) a comparison shows. With `top` > 0 (a queue's "top"): every
/// pair of the `top` variants with the highest `means` (one per variant; NaN ranks last, ties keep the
/// order of first appearance), A the better ranked, in rank order. Else each variant against
/// `reference` when it is one of them; else every pair (A first appeared first) for up to
/// max_all_pairs variants, and each against the first beyond that.
std::vector<std::pair<std::size_t, std::size_t>> compared_pairs(const std::vector<std::string>& variants, const std::string& reference,
                                                                std::size_t top = 0, const std::vector<double>& means = {});

}  // namespace salsa
