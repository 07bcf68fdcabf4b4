// OUT/ranking.csv: within each cell and condition, the variants by their mean, how often each is best,
// and which differ from the best (docs/output-format.md#rankingcsv).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/results/comparison.hpp"
#include "results/comparison_groups.hpp"

namespace salsa::detail {

namespace {

/// The 95 % t-interval of the mean of `v` (NaN for fewer than 2 values).
std::pair<double, double> interval(const Values& v, double mean) {
  double ss = 0;
  for (const auto& [key, x] : v) ss += (x - mean) * (x - mean);
  const double half = t_half_width(v.size(), v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1)) : 0);
  return {mean - half, mean + half};
}

/// Per variant (in `g.variants`' order), the share of the repeats every variant has in which it is best
/// (the highest value; k variants tied for it get 1/k each, so the shares add up to 1), and that number
/// of repeats.
std::pair<std::vector<double>, std::size_t> best_shares(const Group& g) {
  std::vector<double> share(g.variants.size(), 0);
  std::size_t repeats = 0;
  for (const auto& [key, x] : g.values.at(g.variants.front())) {
    std::vector<double> at;
    for (const std::string& v : g.variants) {
      const auto it = g.values.at(v).find(key);
      if (it == g.values.at(v).end()) break;
      at.push_back(it->second);
    }
    if (at.size() != g.variants.size()) continue;
    ++repeats;
    const double top = *std::max_element(at.begin(), at.end());
    const double tied = static_cast<double>(std::count(at.begin(), at.end(), top));
    for (std::size_t v = 0; v < at.size(); ++v)
      if (at[v] == top) share[v] += 1 / tied;
  }
  for (double& s : share) s = repeats ? s / static_cast<double>(repeats) : std::numeric_limits<double>::quiet_NaN();
  return {share, repeats};
}

}  // namespace

std::string ranking_csv(const std::vector<Group>& groups, const std::string& metric) {
  std::string text = "cell,condition";
  for (const char* name : description) text += std::string(",") + name;
  text += ",metric,rank,variant,n,mean,ci_low,ci_high,repeats,best_share,n_vs_best,diff_vs_best,ci_low_vs_best,ci_high_vs_best,differs_from_best\n";
  const auto put = [&](const std::string& field) { (text += ',') += field; };
  for (const Group& g : groups) {
    const std::vector<double> means = variant_means(g);
    // Highest mean first; equal means share a rank and keep the order of first appearance ("top"'s order).
    std::vector<std::size_t> order(g.variants.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return means[a] > means[b]; });
    const auto [share, repeats] = best_shares(g);
    const std::size_t best = order.front();
    for (const std::size_t v : order) {
      const auto rank = 1 + std::count_if(means.begin(), means.end(), [&](double m) { return m > means[v]; });
      const Values& values = g.values.at(g.variants[v]);
      const auto [low, high] = interval(values, means[v]);
      text += csv_field(g.cell);
      put(csv_field(g.condition));
      for (const auto& d : g.description) put(csv_field(d));
      put(csv_field(metric)), put(std::to_string(rank)), put(csv_field(g.variants[v])), put(std::to_string(values.size()));
      for (double x : {means[v], low, high}) put(number(x));
      put(std::to_string(repeats)), put(number(share[v]));
      if (v == best) {
        text += ",,,,,\n";
        continue;
      }
      // comparison.csv's paired t-interval of (variant − best), each at 95 % on its own (no correction).
      const PairedStats s = paired_stats(values, g.values.at(g.variants[best]));
      put(std::to_string(s.n));
      for (double x : {s.mean_diff, s.ci_low, s.ci_high}) put(number(x));
      put(std::isnan(s.ci_low) ? "" : s.ci_low > 0 || s.ci_high < 0 ? "yes" : "no");
      text += '\n';
    }
  }
  return text;
}

}  // namespace salsa::detail
