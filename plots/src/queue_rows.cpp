// A queue folder's tests as its plots group them: OUT/summary.csv's ok tests, swept settings kept apart, in plot order.
#include "salsa/plots/results.hpp"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <set>
#include <tuple>

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/files/csv_reader.hpp"
#include "queue_rows.hpp"

namespace salsa::plots {

namespace fs = std::filesystem;

bool natural_less(std::string_view a, std::string_view b) {
  auto number_at = [](std::string_view s, std::size_t i) {  // a number starts at a digit, or a '-' before one after a non-letter
    return i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) ||
                            (s[i] == '-' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])) &&
                             (i == 0 || !std::isalnum(static_cast<unsigned char>(s[i - 1])))));
  };
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (number_at(a, i) && number_at(b, j)) {
      double x = 0, y = 0;
      const char* ea = std::from_chars(a.data() + i, a.data() + a.size(), x).ptr;
      const char* eb = std::from_chars(b.data() + j, b.data() + b.size(), y).ptr;
      if (x != y) return x < y;
      if (ea > a.data() + i && eb > b.data() + j) {
        i = static_cast<std::size_t>(ea - a.data()), j = static_cast<std::size_t>(eb - b.data());
        continue;
      }
    }
    if (a[i] != b[j]) return a[i] < b[j];
    ++i, ++j;
  }
  return a.size() - i < b.size() - j;
}

std::vector<std::string> in_order(const std::vector<QueueRow>& rows, std::string QueueRow::*key) {
  std::vector<std::string> out;
  for (const auto& r : rows)
    if (std::find(out.begin(), out.end(), r.*key) == out.end()) out.push_back(r.*key);
  return out;
}

std::vector<std::string> sizes_of(const std::vector<QueueRow>& rows) {
  std::map<double, std::string> by_size;
  for (const auto& r : rows) by_size.emplace(r.size, r.drones);
  std::vector<std::string> sizes;
  for (const auto& [n, text] : by_size) sizes.push_back(text);
  return sizes;
}

std::vector<std::string> variants_of(const std::vector<QueueRow>& rows) {
  const auto behaviors = in_order(rows, &QueueRow::behavior);
  std::map<std::string, std::size_t> place;  // variant → its behavior's place
  for (const auto& r : rows)
    place.emplace(r.variant, static_cast<std::size_t>(std::find(behaviors.begin(), behaviors.end(), r.behavior) - behaviors.begin()));
  std::vector<std::string> out = in_order(rows, &QueueRow::variant);
  std::stable_sort(out.begin(), out.end(), [&](const std::string& a, const std::string& b) {
    if (place[a] != place[b]) return place[a] < place[b];
    const bool da = a.ends_with(" (defaults)"), db = b.ends_with(" (defaults)");
    if (da != db) return da;
    return natural_less(a, b);
  });
  return out;
}

std::vector<std::string> conditions_of(const std::vector<QueueRow>& rows) { return in_order(rows, &QueueRow::condition); }

namespace {

/// A setting that differs between tests of one variant, swarm size, condition and repeat is one the
/// queue varies besides them (a sweep.set key: "failures.drone_mtbf"). Each of its values becomes part
/// of the row's condition ("failures.drone_mtbf = 3000"), so the plots keep its values apart.
void split_by_swept_settings(std::vector<QueueRow>& rows, const std::vector<std::vector<std::string>>& settings,
                             const std::vector<std::string>& header, const std::vector<std::size_t>& columns) {
  std::map<std::tuple<std::string, std::string, std::string, std::string>, std::size_t> first;  // the group's first row
  std::vector<bool> swept(columns.size(), false);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto [it, fresh] = first.try_emplace({rows[i].variant, rows[i].drones, rows[i].condition, settings[i].back()}, i);
    if (!fresh)
      for (std::size_t k = 0; k < columns.size(); ++k) swept[k] = swept[k] || settings[i][k] != settings[it->second][k];
  }
  // A setting that follows another swept one value for value says nothing more (failures.camera_mtbf
  // written as 0 exactly where failures.drone_mtbf is set): the first of them names the split.
  for (std::size_t k = 0; k < columns.size(); ++k)
    for (std::size_t j = 0; j < k && swept[k]; ++j) {
      if (!swept[j]) continue;
      std::map<std::string, std::string> k_of_j, j_of_k;
      bool same = true;
      for (std::size_t i = 0; i < rows.size() && same; ++i)
        same = k_of_j.try_emplace(settings[i][j], settings[i][k]).first->second == settings[i][k] &&
               j_of_k.try_emplace(settings[i][k], settings[i][j]).first->second == settings[i][j];
      if (same) swept[k] = false;
    }
  auto shown = [](const std::string& v) {
    if (v.empty()) return std::string("none");
    double x = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    return ec == std::errc() && end == v.data() + v.size() ? Parameter::format(x) : v;  // "3000.0" as 3000
  };
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t k = 0; k < columns.size(); ++k)
      if (swept[k]) rows[i].condition += (rows[i].condition.empty() ? "" : ", ") + header[columns[k]] + " = " + shown(settings[i][k]);
}

}  // namespace

std::vector<QueueRow> read_queue_rows(const fs::path& out, ConditionLabels* labels) {
  CsvReader in(out / "summary.csv");
  const std::size_t c_name = in.column("name"), c_status = in.column("status"), c_variant = in.column("variant"),
                    c_drones = in.column("drones");
  const auto c_found = in.find("fraction_found");  // absent when every test failed: nothing to draw then
  const auto c_behavior = in.find("behavior"), c_condition = in.find("condition"), c_label = in.find("condition_label");
  std::vector<std::pair<std::string, std::size_t>> c_params;  // the single form's behavior.<p>
  for (std::size_t c = 0; c < in.header().size(); ++c)
    if (in.header()[c].starts_with("behavior.")) c_params.emplace_back(in.header()[c].substr(9), c);
  auto text = [&](std::optional<std::size_t> c) { return c ? std::string(in[*c]) : std::string(); };
  // The settings a test was made with (the columns before the outcome's) other than those the plots
  // already group by: one the queue varies (a sweep.set key) splits the groups too, not pooled.
  std::vector<std::size_t> c_settings;
  const auto c_repeat = in.find("repeat");
  for (std::size_t c = 0; c < in.header().size() && !in.header()[c].starts_with("outcome."); ++c) {
    const std::string& h = in.header()[c];
    static const std::set<std::string> grouped{"name", "status", "error", "cell", "variant", "condition", "condition_label",
                                               "behavior", "repeat", "seed", "drones"};
    if (!grouped.contains(h) && !h.starts_with("behavior.") && !h.starts_with("versions.")) c_settings.push_back(c);
  }
  std::vector<QueueRow> rows;
  std::vector<std::vector<std::string>> settings;  // per row, c_settings' values
  while (in.next())
    if (in[c_status] == "ok") {
      QueueRow r{std::string(in[c_name]), std::string(in[c_variant]), std::string(in[c_drones]), text(c_behavior), text(c_condition),
                 text(c_label), in.number(c_drones), in.number(c_found ? *c_found : in.column("fraction_found")) * 100, {}};
      for (const auto& [p, c] : c_params)
        if (const auto v = in.optional_number(c)) r.params[p] = *v;
      settings.emplace_back();
      for (const std::size_t c : c_settings) settings.back().emplace_back(in[c]);
      settings.back().emplace_back(text(c_repeat));  // last: the repeat, to find tests that differ in a setting alone
      rows.push_back(std::move(r));
    }
  if (labels)
    for (const auto& r : rows) labels->emplace(r.condition, r.condition_label);
  split_by_swept_settings(rows, settings, in.header(), c_settings);
  return rows;
}

std::vector<std::string> plotted_conditions(const fs::path& out) {
  std::vector<std::string> out_conditions;
  for (const QueueRow& r : read_queue_rows(out, nullptr)) out_conditions.push_back(r.condition);
  return out_conditions;
}

}  // namespace salsa::plots
