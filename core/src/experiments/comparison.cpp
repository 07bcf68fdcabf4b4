#include "salsa/core/experiments/comparison.hpp"
#include "salsa/core/experiments/queue_summary.hpp"

#include <boost/math/distributions/students_t.hpp>

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <vector>

#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/csv_writer.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {

namespace fs = std::filesystem;

double t_half_width(std::size_t n, double sd) {
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  const boost::math::students_t t(static_cast<double>(n - 1));
  return boost::math::quantile(boost::math::complement(t, 0.025)) * sd / std::sqrt(static_cast<double>(n));
}

namespace {

// Six significant digits, whatever the locale: the file is compared byte for byte.
std::string number(double v) {
  if (std::isnan(v)) return "";
  if (v == 0) v = 0;  // no "-0"
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr;
  return {buf, end};
}

// The columns of summary.csv that describe a cell, copied into each comparison row.
constexpr const char* description[] = {"drones", "targets", "target", "map", "time"};

struct Cell {
  std::string id;
  std::vector<std::string> description;
  std::vector<std::string> variants;                             // in order of first appearance
  std::map<std::string, std::map<std::string, double>> values;   // variant → (repeat, seed) → metric
};

}  // namespace

void write_comparison(const fs::path& out, const std::string& metric) {
  // ---- Read: the ok tests' metric, by cell, variant and (repeat, seed).
  CsvReader in(out / "summary.csv");
  const std::size_t c_cell = in.column("cell"), c_variant = in.column("variant"), c_status = in.column("status"),
                    c_seed = in.column("seed");
  // A queue whose tests all failed has no outcome columns: nothing to compare then.
  const auto c_metric_found = in.find(metric);
  const auto c_repeat = in.find("repeat");
  std::vector<std::optional<std::size_t>> c_description;
  for (const char* name : description) c_description.push_back(in.find(name));
  std::vector<Cell> cells;
  std::map<std::string, std::size_t> cell_index;
  while (in.next()) {
    if (in[c_status] != "ok") continue;
    const std::size_t c_metric = c_metric_found ? *c_metric_found : in.column(metric);  // throws: names the header
    const auto value = in.optional_number(c_metric);
    if (!value) continue;
    const std::string id(in[c_cell]), variant(in[c_variant]);
    auto [it, added] = cell_index.try_emplace(id, cells.size());
    if (added) {
      Cell& c = cells.emplace_back();
      c.id = id;
      for (const auto& k : c_description) c.description.emplace_back(k ? in[*k] : std::string_view{});
    }
    Cell& c = cells[it->second];
    auto& by_seed = c.values[variant];
    if (by_seed.empty()) c.variants.push_back(variant);
    const std::string key = std::string(c_repeat ? in[*c_repeat] : std::string_view{}) + "/" + std::string(in[c_seed]);
    if (!by_seed.emplace(key, *value).second)
      throw InputError(in.file().string() + ": line " + std::to_string(in.line()) + ": a second test of " + variant +
                       " in cell " + id + " with seed " + std::string(in[c_seed]) + " (each pair needs one of each)");
  }

  // ---- Pair and write.
  std::string text = "cell";
  for (const char* name : description) text += std::string(",") + name;
  text += ",metric,variant_a,variant_b,n,mean_a,mean_b,mean_diff,ci_low,ci_high,win_rate_a\n";
  for (const Cell& c : cells)
    for (std::size_t a = 0; a < c.variants.size(); ++a)
      for (std::size_t b = a + 1; b < c.variants.size(); ++b) {
        const auto& va = c.values.at(c.variants[a]);
        const auto& vb = c.values.at(c.variants[b]);
        std::vector<double> diffs;
        double sum_a = 0, sum_b = 0, wins = 0;
        for (const auto& [key, x] : va) {
          const auto y = vb.find(key);
          if (y == vb.end()) continue;
          diffs.push_back(x - y->second);
          sum_a += x, sum_b += y->second;
          wins += x > y->second ? 1 : x == y->second ? 0.5 : 0;
        }
        const auto n = diffs.size();
        const double nan = std::numeric_limits<double>::quiet_NaN();
        double mean = nan, half = nan;
        if (n > 0) {
          mean = 0;
          for (double d : diffs) mean += d;
          mean /= static_cast<double>(n);
          if (n > 1) {
            double ss = 0;
            for (double d : diffs) ss += (d - mean) * (d - mean);
            half = t_half_width(n, std::sqrt(ss / static_cast<double>(n - 1)));
          }
        }
        const double dn = static_cast<double>(n);
        const auto put = [&](const std::string& field) { (text += ',') += field; };
        text += csv_field(c.id);
        for (const auto& d : c.description) put(csv_field(d));
        for (const auto* v : {&metric, &c.variants[a], &c.variants[b]}) put(csv_field(*v));
        put(std::to_string(n));
        for (double v : {n ? sum_a / dn : nan, n ? sum_b / dn : nan, mean, mean - half, mean + half, n ? wins / dn : nan}) put(number(v));
        text += '\n';
      }
  replace_file(out / "comparison.csv", text);
}

}  // namespace salsa
