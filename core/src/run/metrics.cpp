#include "salsa/core/run/metrics.hpp"

#include "salsa/core/files/csv_writer.hpp"  // append_number

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace salsa {

namespace {

std::vector<std::string> split(const char* list) {
  std::vector<std::string> out;
  std::stringstream s(list);
  for (std::string name; std::getline(s, name, ',');) out.push_back(name);
  return out;
}

/// Column names appear in CSV headers and, prefixed by nothing, in the queue summary: a plain identifier.
bool column_name_ok(const std::string& name) {
  auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  return !name.empty() && name.size() <= 64 && letter(name.front()) &&
         std::all_of(name.begin(), name.end(), [&](char c) { return letter(c) || (c >= '0' && c <= '9') || c == '_'; });
}

/// Final columns land in the queue's summary.csv beside its own columns: those names are taken too.
const std::vector<std::string>& queue_columns() {
  static const std::vector<std::string> names = split("name,status,error,cell,variant,behavior,repeat,seed,drones,targets,"
                                                      "target,map,time,versions,wall_seconds");
  return names;
}

std::string format_value(double v, int decimals) {
  if (!std::isfinite(v)) return {};
  if (v == 0) v = 0;  // no "-0.0"
  std::string text;
  append_number(text, v, decimals);
  return text;
}

/// A plugin's message on one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  return text;
}

std::string time_text(double t) {
  std::ostringstream s;
  s.precision(6);
  s << t;
  return s.str();
}

}  // namespace

struct MetricSet::Slot {
  std::string label;  // "metric 'area_coverage' (/path/libmetrics.so)"
  std::shared_ptr<Metric> metric;
  std::vector<Column> step, final;
  std::vector<double> values;  // scratch for observe/finish
};

/// The simulation as a metric sees it.
class MetricSet::View final : public MetricView {
 public:
  const Simulation* sim = nullptr;

  Rect bounds() const override { return sim->bounds(); }
  double time() const override { return sim->time(); }
  double dt() const override { return sim->dt(); }
  std::span<const Vec2> drone_positions() const override { return sim->drone_positions(); }
  std::span<const Vec2> drone_velocities() const override { return sim->drone_velocities(); }
  bool is_free(Vec2 p, double clearance) const override { return sim->is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return sim->ray_cast(from, to); }
  std::span<const TargetState> targets() const override { return sim->targets(); }
  std::size_t targets_found() const override { return sim->targets_found(); }
  std::uint64_t collisions() const override { return sim->collisions(); }
  const DroneProperties& drone(std::uint32_t group) const override { return sim->drone(group); }
  std::span<const std::uint32_t> drone_groups() const override { return sim->drone_groups(); }
  std::span<const DroneStatus> drone_status() const override { return sim->drone_status(); }
  std::size_t group_count() const override { return sim->group_count(); }
  Vec2 base(std::uint32_t group) const override { return sim->base(group); }
  const MapData& map() const override { return sim->map(); }
};

MetricSet::MetricSet(const std::vector<PluginChoice>& metrics, const PluginHost& host) : view_(std::make_unique<View>()) {
  const std::vector<std::string> summary = split(summary_columns), outcome = split(outcome_columns);
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
    Slot slot;
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
    slots_.push_back(std::move(slot));
  }
}

MetricSet::MetricSet(const TestSpec& test, const PluginHost& host) try : MetricSet(test.metrics, host) {
} catch (const MetricListError& e) {
  throw InputError(test.source + ": metrics[" + std::to_string(e.index) + "]: " + e.what());
}

MetricSet::~MetricSet() = default;

std::vector<std::string> MetricSet::step_columns() const {
  std::vector<std::string> out;
  for (const Slot& s : slots_)
    for (const Column& c : s.step) out.push_back(c.name);
  return out;
}

std::vector<std::string> MetricSet::final_columns() const {
  std::vector<std::string> out;
  for (const Slot& s : slots_)
    for (const Column& c : s.final) out.push_back(c.name);
  return out;
}

template <class Call>
void MetricSet::each(const Simulation& sim, const char* what, Call call) {
  view_->sim = &sim;
  for (Slot& s : slots_) {
    try {
      call(s);
    } catch (const std::exception& e) {
      throw MetricFailure(s.label + " failed in " + what + " at t = " + time_text(sim.time()) + " s: " + one_line(e.what()));
    } catch (...) {
      throw MetricFailure(s.label + " failed in " + what + " at t = " + time_text(sim.time()) +
                          " s: an exception that is not a std::exception");
    }
  }
}

void MetricSet::start(const Simulation& sim) {
  stepped_ = sim.step_count();
  each(sim, "reset", [&](Slot& s) { s.metric->reset(*view_); });
}

void MetricSet::after_step(const Simulation& sim) {
  if (sim.step_count() == stepped_) return;  // row() stepped it already
  stepped_ = sim.step_count();
  each(sim, "step", [&](Slot& s) { s.metric->step(*view_); });
}

std::vector<double> MetricSet::observe(const Simulation& sim) {
  after_step(sim);  // observers run inside the step: the metrics see that step first
  each(sim, "observe", [&](Slot& s) {
    s.values.assign(s.step.size(), no_value);
    s.metric->observe(*view_, s.values);
  });
  std::vector<double> out;
  for (const Slot& s : slots_) out.insert(out.end(), s.values.begin(), s.values.end());
  return out;
}

void MetricSet::row(const Simulation& sim, CsvWriter& csv) {
  observe(sim);
  for (const Slot& s : slots_)
    for (std::size_t c = 0; c < s.step.size(); ++c) {
      if (std::isfinite(s.values[c])) csv.field(s.values[c], s.step[c].decimals);
      else csv.empty_field();
    }
}

std::vector<std::pair<std::string, std::string>> MetricSet::finish(const Simulation& sim) {
  after_step(sim);
  std::vector<std::pair<std::string, std::string>> out;
  each(sim, "finish", [&](Slot& s) {
    s.values.assign(s.final.size(), no_value);
    s.metric->finish(*view_, s.values);
  });
  for (const Slot& s : slots_)
    for (std::size_t c = 0; c < s.final.size(); ++c) out.emplace_back(s.final[c].name, format_value(s.values[c], s.final[c].decimals));
  return out;
}

std::string outcome_csv(const Simulation& sim, const std::vector<std::pair<std::string, std::string>>& finals) {
  const std::size_t targets = sim.targets().size(), found = sim.targets_found();
  std::string header = outcome_columns;
  std::string row = std::to_string(targets) + "," + std::to_string(found) + "," +
                    format_value(targets ? static_cast<double>(found) / static_cast<double>(targets) : 0.0, 6);
  for (const auto& [column, text] : finals) {
    header += "," + column;
    row += "," + text;
  }
  return header + "\n" + row + "\n";
}

}  // namespace salsa
