#include "salsa/core/results/comparison.hpp"
#include "salsa/core/results/queue_summary.hpp"

#include <boost/math/distributions/students_t.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/experiments/test_spec.hpp"
#include "results/comparison_groups.hpp"

namespace salsa {

namespace fs = std::filesystem;

double t_half_width(std::size_t n, double sd) {
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const boost::math::students_t t(static_cast<double>(n - 1));
  return boost::math::quantile(boost::math::complement(t, 0.025)) * sd / std::sqrt(static_cast<double>(n));
}

PairedStats paired_stats(const std::map<std::string, double>& a, const std::map<std::string, double>& b) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  PairedStats s{0, nan, nan, nan, nan, nan, nan};
  std::vector<double> diffs;
  double sum_a = 0, sum_b = 0, wins = 0;
  for (const auto& [key, x] : a) {
    const auto y = b.find(key);
    if (y == b.end()) continue;
    diffs.push_back(x - y->second);
    sum_a += x, sum_b += y->second;
    wins += x > y->second ? 1 : x == y->second ? 0.5 : 0;
  }
  s.n = diffs.size();
  if (s.n == 0) return s;
  const double n = static_cast<double>(s.n);
  s.mean_a = sum_a / n, s.mean_b = sum_b / n, s.win_rate_a = wins / n;
  s.mean_diff = 0;
  for (double d : diffs) s.mean_diff += d;
  s.mean_diff /= n;
  if (s.n > 1) {
    double ss = 0;
    for (double d : diffs) ss += (d - s.mean_diff) * (d - s.mean_diff);
    const double half = t_half_width(s.n, std::sqrt(ss / (n - 1)));
    s.ci_low = s.mean_diff - half, s.ci_high = s.mean_diff + half;
  }
  return s;
}

std::vector<std::pair<std::size_t, std::size_t>> compared_pairs(const std::vector<std::string>& variants, const std::string& reference,
                                                                std::size_t top, const std::vector<double>& means) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  if (top > 0) {
    std::vector<std::size_t> rank(variants.size());
    for (std::size_t v = 0; v < rank.size(); ++v) rank[v] = v;
    const auto mean = [&](std::size_t v) { return v < means.size() && !std::isnan(means[v]) ? means[v] : -std::numeric_limits<double>::infinity(); };
    std::stable_sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) { return mean(a) > mean(b); });
    rank.resize(std::min(top, rank.size()));
    for (std::size_t a = 0; a < rank.size(); ++a)
      for (std::size_t b = a + 1; b < rank.size(); ++b) out.emplace_back(rank[a], rank[b]);
    return out;
  }
  auto ref = std::find(variants.begin(), variants.end(), reference);
  if (ref == variants.end() && variants.size() > max_all_pairs) ref = variants.begin();
  if (ref != variants.end()) {
    const auto r = static_cast<std::size_t>(ref - variants.begin());
    for (std::size_t v = 0; v < variants.size(); ++v)
      if (v != r) out.emplace_back(v, r);
    return out;
  }
  for (std::size_t a = 0; a < variants.size(); ++a)
    for (std::size_t b = a + 1; b < variants.size(); ++b) out.emplace_back(a, b);
  return out;
}

namespace {

using detail::Group;
using detail::number;
using detail::Values;
using detail::description;
using detail::variant_means;

/// Which pairs to show, as OUT/queue.json records the queue's "reference" and "top" ("" and 0: none).
struct Choice {
  std::string reference;
  std::size_t top = 0;
  bool recorded = false;  // OUT/queue.json is there: the queue's choice, not an assumption
};
Choice recorded_choice(const fs::path& out) {
  Choice c;
  std::ifstream in(out / "queue.json", std::ios::binary);
  if (!in) return c;
  std::stringstream text;
  text << in.rdbuf();
  try {
    const auto j = nlohmann::json::parse(text.str());
    if (!j.is_object()) return c;
    c.recorded = true;
    if (j.contains("reference") && j["reference"].is_string()) c.reference = j["reference"].get<std::string>();
    if (j.contains("top") && j["top"].is_number_unsigned()) c.top = j["top"].get<std::size_t>();
  } catch (const std::exception&) {
  }
  return c;
}

/// The per-pair differences A − B of a group, by "repeat/seed".
Values differences(const Group& g, const std::string& a, const std::string& b) {
  Values out;
  const Values& va = g.values.at(a);
  const Values& vb = g.values.at(b);
  for (const auto& [key, x] : va)
    if (const auto y = vb.find(key); y != vb.end()) out[key] = x - y->second;
  return out;
}

/// The same differences keyed by repeat alone (a condition that changes the world changes the seeds),
/// or empty when a repeat is there twice.
Values by_repeat(const Values& v) {
  Values out;
  for (const auto& [key, x] : v)
    if (!out.emplace(key.substr(0, key.find('/')), x).second) return {};
  return out;
}

/// The 95 % t-interval of the mean of `v`'s values at the keys `other` has too (NaN for fewer than 2).
std::pair<double, double> mean_interval(const Values& v, const Values& other) {
  std::vector<double> x;
  for (const auto& [key, value] : v)
    if (other.count(key)) x.push_back(value);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (x.size() < 2) return {nan, nan};
  double mean = 0, ss = 0;
  for (double e : x) mean += e;
  mean /= static_cast<double>(x.size());
  for (double e : x) ss += (e - mean) * (e - mean);
  const double half = t_half_width(x.size(), std::sqrt(ss / static_cast<double>(x.size() - 1)));
  return {mean - half, mean + half};
}

/// What a comparison without OUT/queue.json took from the folders' order ("" when nothing): the
/// baseline condition (the first) and the pairs (no reference: every two variants, or each against the
/// first beyond max_all_pairs).
std::string assumed(const std::vector<Group>& groups, bool conditions) {
  std::string out;
  if (conditions) out = "the baseline is condition '" + groups.front().condition + "' (the first in folder order)";
  const auto many = std::find_if(groups.begin(), groups.end(), [](const Group& g) { return g.variants.size() > max_all_pairs; });
  std::string pairs;
  if (many != groups.end()) pairs = "pairs are each variant against '" + many->variants.front() + "' (the first in folder order)";
  else if (std::any_of(groups.begin(), groups.end(), [](const Group& g) { return g.variants.size() > 1; }))
    pairs = "pairs are every two variants (no reference)";
  if (!out.empty() && !pairs.empty()) out += " and ";
  return out + pairs;
}

}  // namespace

std::string write_comparison(const fs::path& out, const std::string& metric, const std::optional<Pairing>& pairing) {
  // ---- Read: the ok tests' metric, by cell and condition, variant and (repeat, seed).
  CsvReader in(out / "summary.csv");
  const std::size_t c_cell = in.column("cell"), c_variant = in.column("variant"), c_status = in.column("status"),
                    c_seed = in.column("seed");
  // A queue whose tests all failed has no outcome columns: nothing to compare then.
  const auto c_metric_found = in.find(metric);
  const auto c_repeat = in.find("repeat");
  const auto c_condition = in.find("condition");  // summaries written before conditions have none
  std::vector<std::optional<std::size_t>> c_description;
  for (const char* name : description) c_description.push_back(in.find(name));
  std::vector<Group> groups;
  std::map<std::pair<std::string, std::string>, std::size_t> group_index;
  while (in.next()) {
    if (in[c_status] != "ok") continue;
    const std::size_t c_metric = c_metric_found ? *c_metric_found : in.column(metric);  // throws: names the header
    const auto value = in.optional_number(c_metric);
    if (!value) continue;
    const std::string id(in[c_cell]), variant(in[c_variant]), condition(c_condition ? in[*c_condition] : std::string_view{});
    auto [it, added] = group_index.try_emplace({id, condition}, groups.size());
    if (added) {
      Group& g = groups.emplace_back();
      g.cell = id, g.condition = condition;
      for (const auto& k : c_description) g.description.emplace_back(k ? in[*k] : std::string_view{});
    }
    Group& g = groups[it->second];
    auto& by_seed = g.values[variant];
    if (by_seed.empty()) g.variants.push_back(variant);
    const std::string key = std::string(c_repeat ? in[*c_repeat] : std::string_view{}) + "/" + std::string(in[c_seed]);
    if (!by_seed.emplace(key, *value).second)
      throw InputError(in.file().string() + ": line " + std::to_string(in.line()) + ": a second test of " + variant +
                       " in cell " + id + (condition.empty() ? "" : " under condition " + condition) + " with seed " +
                       std::string(in[c_seed]) + " (each pair needs one of each)");
  }
  Choice choice = recorded_choice(out);
  if (pairing) choice.reference = pairing->reference, choice.top = pairing->top;
  const auto pairs_of = [&](const Group& g) { return compared_pairs(g.variants, choice.reference, choice.top, variant_means(g)); };
  const auto put = [](std::string& text, const std::string& field) { (text += ',') += field; };
  auto put_numbers = [&](std::string& text, std::initializer_list<double> values) {
    for (double v : values) put(text, number(v));
  };

  // ---- comparison.csv: the pairs within each cell and condition.
  std::string text = "cell,condition";
  for (const char* name : description) text += std::string(",") + name;
  text += ",metric,variant_a,variant_b,n,mean_a,mean_b,mean_diff,ci_low,ci_high,win_rate_a\n";
  for (const Group& g : groups)
    for (const auto& [a, b] : pairs_of(g)) {
      const PairedStats s = paired_stats(g.values.at(g.variants[a]), g.values.at(g.variants[b]));
      text += csv_field(g.cell);
      put(text, csv_field(g.condition));
      for (const auto& d : g.description) put(text, csv_field(d));
      for (const auto* v : {&metric, &g.variants[a], &g.variants[b]}) put(text, csv_field(*v));
      put(text, std::to_string(s.n));
      put_numbers(text, {s.mean_a, s.mean_b, s.mean_diff, s.ci_low, s.ci_high, s.win_rate_a});
      text += '\n';
    }
  replace_file(out / "comparison.csv", text);
  replace_file(out / "ranking.csv", detail::ranking_csv(groups, metric));

  // ---- did.csv: within each cell, whether A − B changes from the first condition to each other one.
  std::string did = "cell";
  for (const char* name : description) did += std::string(",") + name;
  did += ",metric,variant_a,variant_b,baseline,condition,n,diff_baseline,diff_condition,did,ci_low,ci_high\n";
  std::vector<std::string> cells;                           // in order of first appearance
  std::map<std::string, std::vector<std::size_t>> in_cell;  // cell → its groups, the baseline first
  for (std::size_t i = 0; i < groups.size(); ++i) {
    auto& list = in_cell[groups[i].cell];
    if (list.empty()) cells.push_back(groups[i].cell);
    list.push_back(i);
  }
  // condition_effects.csv: within each cell, each variant under each later condition against itself
  // under the first.
  std::string effects = "cell";
  for (const char* name : description) effects += std::string(",") + name;
  effects += ",metric,variant,baseline,condition,n,mean_baseline,baseline_ci_low,baseline_ci_high,mean_condition,mean_diff,ci_low,ci_high,win_rate\n";
  bool any = false;
  for (const std::string& cell : cells) {
    const std::vector<std::size_t>& list = in_cell[cell];
    const Group& base = groups[list.front()];
    for (std::size_t k = 1; k < list.size(); ++k) {
      const Group& other = groups[list[k]];
      any = true;
      for (const std::string& v : base.variants) {
        if (!other.values.count(v)) continue;
        Values x0 = base.values.at(v), x1 = other.values.at(v);
        // Paired by repeat and seed when the condition keeps the worlds, else by repeat.
        if (std::none_of(x1.begin(), x1.end(), [&](const auto& e) { return x0.count(e.first); })) x0 = by_repeat(x0), x1 = by_repeat(x1);
        const PairedStats s = paired_stats(x1, x0);
        const auto [low, high] = mean_interval(x0, x1);
        effects += csv_field(base.cell);
        for (const auto& d : base.description) put(effects, csv_field(d));
        for (const auto* e : {&metric, &v, &base.condition, &other.condition}) put(effects, csv_field(*e));
        put(effects, std::to_string(s.n));
        put_numbers(effects, {s.mean_b, low, high, s.mean_a, s.mean_diff, s.ci_low, s.ci_high, s.win_rate_a});
        effects += '\n';
      }
      for (const auto& [a, b] : pairs_of(base)) {
        const std::string &va = base.variants[a], &vb = base.variants[b];
        if (!other.values.count(va) || !other.values.count(vb)) continue;
        Values d0 = differences(base, va, vb), d1 = differences(other, va, vb);
        // Paired by repeat and seed when the condition keeps the worlds, else by repeat.
        if (std::none_of(d1.begin(), d1.end(), [&](const auto& e) { return d0.count(e.first); })) d0 = by_repeat(d0), d1 = by_repeat(d1);
        const PairedStats s = paired_stats(d1, d0);
        did += csv_field(base.cell);
        for (const auto& d : base.description) put(did, csv_field(d));
        for (const auto* v : {&metric, &va, &vb, &base.condition, &other.condition}) put(did, csv_field(*v));
        put(did, std::to_string(s.n));
        put_numbers(did, {s.mean_b, s.mean_a, s.mean_diff, s.ci_low, s.ci_high});
        did += '\n';
      }
    }
  }
  std::error_code ec;
  if (any) {
    replace_file(out / "did.csv", did);
    replace_file(out / "condition_effects.csv", effects);
  } else {
    // A queue without conditions has neither (those left from an earlier queue go).
    for (const char* name : {"did.csv", "condition_effects.csv"}) fs::remove(out / name, ec);
  }
  return choice.recorded ? std::string() : assumed(groups, any);
}

std::vector<std::string> queue_variants(const fs::path& out) {
  CsvReader in(out / "summary.csv");
  const std::size_t c_variant = in.column("variant");
  std::vector<std::string> out_variants;
  while (in.next())
    if (std::find(out_variants.begin(), out_variants.end(), in[c_variant]) == out_variants.end()) out_variants.emplace_back(in[c_variant]);
  return out_variants;
}

}  // namespace salsa
