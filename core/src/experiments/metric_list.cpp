// The columns a test's data files will have (metric_list.hpp): its metrics made and their columns checked.
#include "salsa/core/experiments/metric_list.hpp"

#include <algorithm>
#include <sstream>
#include <utility>

#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/files/input_error.hpp"

namespace salsa {

namespace {

/// Column names appear in CSV headers and, prefixed by nothing, in the queue summary: a plain identifier.
bool column_name_ok(const std::string& name) {
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  return !name.empty() && name.size() <= 64 && letter(name.front()) &&
         std::all_of(name.begin(), name.end(), [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '_'; });
}

/// Final columns land in the queue's summary.csv beside its own columns: those names are taken too.
const std::vector<std::string>& queue_columns() {
  static const std::vector<std::string> names = split_columns("name,status,error,cell,variant,behavior,repeat,seed,drones,targets,"
                                                              "target,map,time,versions,wall_seconds");
  return names;
}

/// A plugin's message on one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

}  // namespace

std::vector<std::string> split_columns(const char* list) {
  std::vector<std::string> out;
  std::stringstream s(list);
  for (std::string name; std::getline(s, name, ',');) out.push_back(name);
  return out;
}

std::vector<MetricSlot> make_metrics(const std::vector<PluginChoice>& metrics, const PluginHost& host) {
  std::vector<MetricSlot> out;
  const std::vector<std::string> summary = split_columns(summary_columns), outcome = split_columns(outcome_columns);
  // Who holds each column name so far, per file.
  std::vector<std::pair<std::string, std::string>> step_owner, final_owner;
  for (const auto& o : outcome) final_owner.emplace_back(o, "outcome.csv's own columns");
  for (const auto& q : queue_columns()) final_owner.emplace_back(q, "the queue summary's own columns");
  for (const auto& s : summary) step_owner.emplace_back(s, "summary.csv's own columns");

  for (std::size_t i = 0; i < metrics.size(); ++i) {
    const PluginChoice& choice = metrics[i];
    for (std::size_t k = 0; k < i; ++k)
      if (metrics[k].name == choice.name)
        throw MetricListError(i, "metric '" + choice.name + "' is listed twice (also metrics[" + std::to_string(k) +
                                     "]; allowed: each metric once)");
    MetricSlot slot;
    const char* call = "";  // the metric's own call that threw, once it exists
    try {
      const Entry<Metric>& entry = host.metric(choice.name);
      slot.label = "metric '" + choice.name + "' (" + entry.plugin().file.string() + ")";
      slot.metric = PluginHost::create(entry, choice.params);  // its message names the metric
      call = "step_columns";
      slot.step = slot.metric->step_columns();
      call = "final_columns";
      slot.final = slot.metric->final_columns();
    } catch (const std::exception& e) {
      throw MetricListError(i, one_line(*call ? slot.label + " failed in " + call + ": " + e.what() : e.what()));
    } catch (...) {
      throw MetricListError(i, *call ? slot.label + " failed in " + call + ": an exception that is not a std::exception"
                                     : "metric '" + choice.name + "': an exception that is not a std::exception");
    }
    auto claim = [&](const std::vector<Column>& columns, std::vector<std::pair<std::string, std::string>>& owners,
                     const char* file) {
      for (const Column& c : columns) {
        const std::string at = slot.label + ": " + file + " column \"" + c.name.substr(0, 60) + "\"";
        if (!column_name_ok(c.name))
          throw MetricListError(i, at + " is not a valid column name (allowed: a letter, then letters, digits and '_', 1 to 64 characters)");
        if (c.decimals < 0 || c.decimals > 12)
          throw MetricListError(i, at + ": decimals " + std::to_string(c.decimals) + " (allowed: 0 to 12)");
        for (const auto& [name, owner] : owners)
          if (name == c.name)
            throw MetricListError(i, at + " is already one of " + owner + " (allowed: distinct column names; list only one of the two metrics)");
        owners.emplace_back(c.name, "metric '" + choice.name + "''s columns");
      }
    };
    claim(slot.step, step_owner, "summary.csv");
    claim(slot.final, final_owner, "outcome.csv");
    out.push_back(std::move(slot));
  }
  return out;
}

std::vector<MetricSlot> make_metrics(const TestSpec& test, const PluginHost& host) try {
  return make_metrics(test.metrics, host);
} catch (const MetricListError& e) {
  throw InputError(test.source + ": metrics[" + std::to_string(e.index) + "]: " + e.what());
}

/// The columns of summary.csv and outcome.csv a run of `test` writes, known before it runs: salsa's, the
/// metrics', then the models' (docs/output-format.md). Throws InputError for a bad metric list.
DataColumns data_columns(const TestSpec& test, const PluginHost& host) {
  std::vector<std::string> step, final;
  for (const MetricSlot& m : make_metrics(test, host)) {
    for (const Column& c : m.step) step.push_back(c.name);
    for (const Column& c : m.final) final.push_back(c.name);
  }
  const std::vector<std::string> models = ModelOutputs(test).columns();
  DataColumns c{split_columns(summary_columns), split_columns(outcome_columns)};
  for (const auto& [to, more] : {std::pair{&c.summary, &step}, std::pair{&c.outcome, &final}}) {
    to->insert(to->end(), more->begin(), more->end());
    to->insert(to->end(), models.begin(), models.end());
  }
  return c;
}

}  // namespace salsa
