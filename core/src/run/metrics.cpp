#include "salsa/core/run/metrics.hpp"

#include "salsa/core/files/csv_writer.hpp"  // append_number

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

namespace salsa {

namespace {

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

struct MetricSet::Slot : MetricSlot {
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

MetricSet::MetricSet(const std::vector<PluginChoice>& metrics, const PluginHost& host) : MetricSet(make_metrics(metrics, host)) {}

MetricSet::MetricSet(const TestSpec& test, const PluginHost& host) : MetricSet(make_metrics(test, host)) {}

MetricSet::MetricSet(std::vector<MetricSlot> metrics) : view_(std::make_unique<View>()) {
  for (MetricSlot& m : metrics) slots_.push_back({std::move(m), {}});
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
