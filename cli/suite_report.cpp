// The suite's results: the scored tests of each task's queue folder, the references file (one row per
// reference behavior, task, condition and world, values as summary.csv wrote them, so a rerun compares
// byte for byte), its table of means, and the report placing a behavior among the references.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <numeric>

#include "salsa/core/files/csv_reader.hpp"
#include "salsa/core/files/input_error.hpp"
#include "salsa/core/results/comparison.hpp"
#include "salsa/core/results/queue_summary.hpp"
#include "salsa/plots/results.hpp"
#include "suite.hpp"

namespace fs = std::filesystem;

namespace salsa::cli {

namespace {

constexpr const char* references_header = "version,task,condition,variant,repeat,seed,metric,value";

// Six significant digits, whatever the locale, as comparison.csv writes them.
std::string number(double v) {
  if (std::isnan(v)) return "";
  if (v == 0) v = 0;  // no "-0"
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6).ptr;
  return {buf, end};
}

const SuiteTask& task_named(const Suite& suite, const std::string& name) {
  for (const SuiteTask& t : suite.tasks)
    if (t.name == name) return t;
  throw InputError(suite.file.string() + ": no task '" + name + "'");
}

/// One variant's values on one task and condition: "repeat/seed" → value (ok tests with a value).
using Values = std::map<std::string, double>;

/// The values of one task and condition, by variant in order of first appearance.
struct Group {
  std::string task, condition;
  std::vector<std::string> variants;
  std::vector<Values> values;
};

std::vector<Group> grouped(const std::vector<SuiteValue>& values) {
  std::vector<Group> groups;
  for (const SuiteValue& v : values) {
    auto g = std::find_if(groups.begin(), groups.end(), [&](const Group& x) { return x.task == v.task && x.condition == v.condition; });
    if (g == groups.end()) g = groups.insert(groups.end(), Group{v.task, v.condition, {}, {}});
    auto at = std::find(g->variants.begin(), g->variants.end(), v.variant);
    if (at == g->variants.end()) g->variants.push_back(v.variant), g->values.emplace_back(), at = g->variants.end() - 1;
    if (!v.value.empty()) g->values[static_cast<std::size_t>(at - g->variants.begin())][std::to_string(v.repeat) + "/" + v.seed] = std::stod(v.value);
  }
  return groups;
}

struct Summary {
  std::size_t n = 0;
  double mean = NAN, lo = NAN, hi = NAN;
};

Summary summary(const Values& values) {
  Summary s;
  s.n = values.size();
  if (s.n == 0) return s;
  double sum = 0;
  for (const auto& [k, v] : values) sum += v;
  s.mean = sum / static_cast<double>(s.n);
  double ss = 0;
  for (const auto& [k, v] : values) ss += (v - s.mean) * (v - s.mean);
  const double half = s.n > 1 ? t_half_width(s.n, std::sqrt(ss / static_cast<double>(s.n - 1))) : NAN;
  s.lo = s.mean - half, s.hi = s.mean + half;
  return s;
}

std::string interval(const Summary& s) {
  if (s.n == 0) return "—";
  return number(s.mean) + (std::isnan(s.lo) ? "" : " [" + number(s.lo) + ", " + number(s.hi) + "]");
}

/// "| a | b |" from cells; the behavior's own row in bold.
std::string md_row(const std::vector<std::string>& cells) {
  std::string line = "|";
  for (const auto& c : cells) line += " " + c + " |";
  return line + "\n";
}

std::string better_words(const SuiteTask& t) { return t.higher_better ? "higher is better" : "lower is better"; }

/// The table of every variant's mean and 95 % interval under each condition of one task.
std::string means_table(const std::vector<Group>& groups, const std::string& task, const std::string& bold) {
  std::vector<const Group*> mine;
  for (const Group& g : groups)
    if (g.task == task) mine.push_back(&g);
  if (mine.empty()) return "";
  std::vector<std::string> head{"behavior"}, rule{"---"};
  for (const Group* g : mine) head.push_back(g->condition), rule.push_back("---");
  std::string text = md_row(head) + md_row(rule);
  for (std::size_t v = 0; v < mine.front()->variants.size(); ++v) {
    const std::string& name = mine.front()->variants[v];
    std::vector<std::string> row{name == bold ? "**" + name + "**" : name};
    for (const Group* g : mine) {
      const auto at = std::find(g->variants.begin(), g->variants.end(), name);
      row.push_back(at == g->variants.end() ? "—" : interval(summary(g->values[static_cast<std::size_t>(at - g->variants.begin())])));
    }
    text += md_row(row);
  }
  return text;
}

}  // namespace

std::vector<SuiteValue> task_values(const fs::path& folder, const SuiteTask& task) {
  CsvReader in(folder / "summary.csv");
  const std::size_t c_status = in.column("status"), c_variant = in.column("variant"), c_condition = in.column("condition"),
                    c_repeat = in.column("repeat"), c_seed = in.column("seed");
  const auto c_metric = in.find(task.metric);
  if (!c_metric)
    throw InputError((folder / "summary.csv").string() + ": no column '" + task.metric + "', the metric of task '" + task.name +
                     "' (allowed: a column of summary.csv; add its metric plugin to the task's \"metrics\")");
  std::vector<SuiteValue> out;
  while (in.next())
    out.push_back({task.name, std::string(in[c_condition]), std::string(in[c_variant]), static_cast<std::uint64_t>(in.number(c_repeat)),
                   std::string(in[c_seed]), in[c_status] == "ok" ? std::string(in[*c_metric]) : ""});
  return out;
}

void write_references(const Suite& suite, const std::vector<SuiteValue>& values, const fs::path& file) {
  std::string text = std::string(references_header) + "\n";
  for (const SuiteValue& v : values)
    text += std::to_string(suite.version) + "," + csv_field(v.task) + "," + csv_field(v.condition) + "," + csv_field(v.variant) + "," +
            std::to_string(v.repeat) + "," + v.seed + "," + csv_field(task_named(suite, v.task).metric) + "," + v.value + "\n";
  replace_file(file, text);
}

std::vector<SuiteValue> read_references(const Suite& suite, const fs::path& file) {
  if (!fs::is_regular_file(file))
    throw InputError(file.string() + ": no references file (write it with 'salsa suite --references')");
  CsvReader in(file);
  const std::size_t c_version = in.column("version"), c_task = in.column("task"), c_condition = in.column("condition"),
                    c_variant = in.column("variant"), c_repeat = in.column("repeat"), c_seed = in.column("seed"), c_value = in.column("value");
  std::vector<SuiteValue> out;
  while (in.next()) {
    if (in.number(c_version) != static_cast<double>(suite.version))
      throw InputError(file.string() + ": line " + std::to_string(in.line()) + ": version " + std::string(in[c_version]) + ", not the suite's " +
                       std::to_string(suite.version) + " (regenerate with 'salsa suite --references')");
    out.push_back({std::string(in[c_task]), std::string(in[c_condition]), std::string(in[c_variant]),
                   static_cast<std::uint64_t>(in.number(c_repeat)), std::string(in[c_seed]), std::string(in[c_value])});
    (void)task_named(suite, out.back().task);
  }
  return out;
}

void write_reference_table(const Suite& suite, const std::vector<SuiteValue>& values, const fs::path& file) {
  const auto groups = grouped(values);
  std::string text = "# Suite version " + std::to_string(suite.version) + ": reference results\n\n" +
                     "Mean and 95 % interval (Student's t) over " + std::to_string(suite.repeats) +
                     " paired worlds (queue seed " + std::to_string(suite.seed) + ") of each reference behavior, per task and condition. "
                     "Written by `salsa suite --references` from " + file.stem().string() + ".csv's values; see docs/suite.md.\n";
  for (const SuiteTask& t : suite.tasks)
    text += "\n## " + t.name + " (`" + t.metric + "`, " + better_words(t) + ")\n\n" + means_table(groups, t.name, "");
  replace_file(file, text);
}

void write_report(const Suite& suite, const std::string& behavior, const std::vector<SuiteValue>& values, const fs::path& out,
                  const std::string& note) {
  const auto groups = grouped(values);
  std::string csv = "task,condition,metric,better,behavior,reference,n,mean_behavior,mean_reference,mean_diff,ci_low,ci_high,better_share,rank,ranked\n";
  std::string md = "# " + behavior + " on suite version " + std::to_string(suite.version) + "\n\n" + note +
                   " Differences are the behavior's value less the reference's on the same world (repeat and seed), "
                   "with their 95 % interval (Student's t over the pairs); rank 1 is the best mean under the condition.\n";
  fs::create_directories(out / "plots");
  plots::start_plotting();
  for (const SuiteTask& t : suite.tasks) {
    md += "\n## " + t.name + " (`" + t.metric + "`, " + better_words(t) + ")\n\n" + means_table(groups, t.name, behavior);
    std::vector<std::string> head{"difference from", }, rule{"---"};
    std::map<std::string, std::vector<std::string>> diff_rows;  // reference → cells
    std::vector<std::string> refs, ranks{"rank"};
    std::vector<plots::Estimate> estimates;
    for (const Group& g : groups) {
      if (g.task != t.name) continue;
      const auto me = std::find(g.variants.begin(), g.variants.end(), behavior);
      if (me == g.variants.end()) continue;
      const Values& mine = g.values[static_cast<std::size_t>(me - g.variants.begin())];
      head.push_back(g.condition), rule.push_back("---");
      // The rank among the variants with a mean: 1 + those strictly better.
      const Summary own = summary(mine);
      std::size_t rank = 1, ranked = 0;
      for (const Values& v : g.values) {
        const Summary s = summary(v);
        if (std::isnan(s.mean)) continue;
        ++ranked;
        if (!std::isnan(own.mean) && (t.higher_better ? s.mean > own.mean : s.mean < own.mean)) ++rank;
      }
      const std::string rank_text = std::isnan(own.mean) ? "" : std::to_string(rank);
      ranks.push_back(rank_text.empty() ? "—" : rank_text + " of " + std::to_string(ranked));
      for (std::size_t r = 0; r < g.variants.size(); ++r) {
        if (g.variants[r] == behavior) continue;
        const PairedStats p = paired_stats(mine, g.values[r]);
        if (!mine.empty() && !g.values[r].empty() && p.n == 0)
          throw InputError(suite.results.string() + ": no world of task '" + t.name + "' under '" + g.condition + "' shared by " + behavior +
                           " and " + g.variants[r] + " (the references were made on other seeds: regenerate them with 'salsa suite --references')");
        const double share = p.n ? (t.higher_better ? p.win_rate_a : 1 - p.win_rate_a) : NAN;
        csv += csv_field(t.name) + "," + csv_field(g.condition) + "," + csv_field(t.metric) + "," + (t.higher_better ? "higher" : "lower") + "," +
               csv_field(behavior) + "," + csv_field(g.variants[r]) + "," + std::to_string(p.n) + "," + number(p.mean_a) + "," + number(p.mean_b) + "," +
               number(p.mean_diff) + "," + number(p.ci_low) + "," + number(p.ci_high) + "," + number(share) + "," + rank_text + "," +
               std::to_string(ranked) + "\n";
        if (!diff_rows.count(g.variants[r])) refs.push_back(g.variants[r]);
        diff_rows[g.variants[r]].push_back(p.n ? number(p.mean_diff) + (std::isnan(p.ci_low) ? "" : " [" + number(p.ci_low) + ", " + number(p.ci_high) + "]")
                                               : "—");
        auto opt = [](double v) { return std::isnan(v) ? std::optional<double>() : std::optional<double>(v); };
        estimates.push_back({g.condition, "− " + g.variants[r], "n = " + std::to_string(p.n), opt(p.mean_diff), opt(p.ci_low), opt(p.ci_high)});
      }
    }
    md += "\n" + md_row(head) + md_row(rule);
    for (const auto& r : refs) {
      std::vector<std::string> row{r};
      row.insert(row.end(), diff_rows[r].begin(), diff_rows[r].end());
      md += md_row(row);
    }
    md += md_row(ranks);
    md += "\n![" + behavior + " − each reference, " + t.name + "](plots/suite_" + t.name + ".png)\n";
    plots::draw_estimates(estimates, t.name + ": " + behavior + " − each reference in " + t.metric + " (" + better_words(t) + "; mean, 95 % CI)",
                          "difference (" + t.metric + ")", out / "plots" / ("suite_" + t.name + ".png"));
  }
  replace_file(out / "report.csv", csv);
  replace_file(out / "report.md", md);
}

}  // namespace salsa::cli
