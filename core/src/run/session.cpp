#include "salsa/core/run/session.hpp"

#include <algorithm>
#include <cmath>

#include "format.hpp"

namespace salsa {

std::string failed_plugin(const PluginFailure& failure, const TestSpec& test, const PluginHost& host) {
  std::string name;
  std::filesystem::path file;
  try {
    if (failure.kind == "behavior" && failure.index < test.groups.size()) {
      name = test.groups[failure.index].behavior.name;
      file = host.behavior(name).plugin().file;
    } else if (failure.kind == "target kind") {
      name = test.target.name;
      file = host.target_kind(name).plugin().file;
    } else if (failure.kind == "contact handler" && failure.index < test.contact_handlers.size()) {
      name = test.contact_handlers[failure.index].name;
      file = host.contact_handler(name).plugin().file;
    } else if (failure.kind == "map") {
      name = test.map.name;
      file = host.map(name).plugin().file;
    } else if (failure.kind == "wind" && !test.wind_field.name.empty()) {
      name = test.wind_field.name;
      file = host.wind(name).plugin().file;
    } else if (failure.kind == "metric" && failure.index < test.metrics.size()) {
      name = test.metrics[failure.index].name;
      file = host.metric(name).plugin().file;
    }
  } catch (const std::exception&) {  // unknown to this host: the name alone
  }
  std::string out = failure.kind;
  if (failure.kind == "contact handler" && name.empty()) out += " #" + std::to_string(failure.index);
  if (!name.empty()) out += " '" + name + "'";
  if (failure.kind == "behavior" && test.named_groups && failure.index < test.groups.size())
    out += " of group '" + test.groups[failure.index].name + "'";
  if (!file.empty()) out += " (" + file.string() + ")";
  return out;
}

SummaryRow summary_row(const Simulation& sim) {
  SummaryRow row;
  row.time = sim.time();
  double sum = 0;
  const auto status = sim.drone_status();
  const auto velocities = sim.drone_velocities();
  for (std::size_t i = 0; i < velocities.size(); ++i) {
    if (status[i] != DroneStatus::flying) continue;
    const double s = velocities[i].length();
    sum += s;
    row.max_speed = std::max(row.max_speed, s);
  }
  double nn_sum = 0;
  std::size_t nn_count = 0;
  for (double d : sim.nearest_neighbour_distances())
    if (std::isfinite(d)) nn_sum += d, ++nn_count;
  const std::size_t n = sim.flying_count(), targets = sim.targets().size();
  row.targets_found = sim.targets_found();
  row.fraction_found = targets ? static_cast<double>(row.targets_found) / static_cast<double>(targets) : 0.0;
  row.mean_speed = n ? sum / static_cast<double>(n) : 0.0;
  if (nn_count) row.mean_nn_distance = nn_sum / static_cast<double>(nn_count);
  row.collisions = sim.collisions();
  return row;
}

const char* status_name(const Simulation& sim, std::uint32_t id) {
  switch (sim.drone_status()[id]) {
    case DroneStatus::flying:
      switch (sim.errand(id)) {  // return to base's errands first: what the drone is doing now
        case Errand::returning: return "returning";
        case Errand::charging: return "charging";
        case Errand::outbound: return "outbound";
        case Errand::none: break;
      }
      return sim.camera_works(id) ? "flying" : "camera_failed";
    case DroneStatus::landed: return "landed";
    case DroneStatus::failed: return "failed";
    case DroneStatus::removed: return "removed";
  }
  return "?";
}

Session::Session(TestSpec test, const PluginHost& host, SessionOptions options)
    : test_(std::move(test)), current_(test_), host_(&host), timeline_(test_.changes) {
  try {
    SimulationSetup setup = make_setup(test_, host, options.threads);
    if (options.behavior) setup.groups[0].behavior = std::move(options.behavior);
    sim_ = std::make_unique<Simulation>(std::move(setup));
    metrics_ = std::make_unique<MetricSet>(test_, host);
  } catch (const PluginFailure& e) {
    throw TestFailure(where() + ": could not start: " + failed_plugin(e, test_, host) + " failed: " + e.what());
  } catch (const std::exception& e) {
    throw TestFailure(where() + ": could not start: " + e.what());
  }
  try {
    metrics_->start(*sim_);
  } catch (const MetricFailure& e) {
    throw TestFailure(where() + ": " + e.what());
  }
}

Session::~Session() = default;

std::string Session::where() const { return "test '" + test_.name + "' (" + test_.source + ")"; }

bool Session::finished() const { return sim_->step_count() >= test_.steps(); }

void Session::apply_due_changes() {
  // A change applies right before the step that starts at its time.
  for (; next_change_ < timeline_.size() && change_step(timeline_[next_change_].time, sim_->dt()) <= sim_->step_count(); ++next_change_) {
    const Change& c = timeline_[next_change_];
    try {
      apply_change(*sim_, current_, c, *host_);
    } catch (const std::exception& e) {
      const auto* plugin = dynamic_cast<const PluginFailure*>(&e);
      throw TestFailure(where() + ": the change at t = " + format::seconds(c.time) + " s (" + c.key + ") could not be applied: " +
                        (plugin ? failed_plugin(*plugin, current_, *host_) + " failed: " : "") + e.what());
    }
  }
}

void Session::step() {
  apply_due_changes();
  try {
    sim_->step();
    metrics_->after_step(*sim_);
  } catch (const WriteError&) {
    throw;  // an observer's file: the caller knows which
  } catch (const MetricFailure& e) {
    throw TestFailure(where() + ": " + e.what());
  } catch (const PluginFailure& e) {
    throw TestFailure(where() + ": " + failed_plugin(e, current_, *host_) + " failed at t = " + format::seconds(sim_->time()) +
                      " s: " + e.what());
  } catch (const std::exception& e) {  // not plugin code
    throw TestFailure(where() + ": failed at t = " + format::seconds(sim_->time()) + " s: " + e.what());
  }
}

void Session::change(const std::string& key, double value) {
  const Change c{sim_->time(), key, value};
  try {
    apply_change(*sim_, current_, c, *host_);  // throws when refused, leaving both as they were
  } catch (const PluginFailure& e) {
    throw std::invalid_argument(key + ": " + failed_plugin(e, current_, *host_) + " failed: " + e.what());
  }
  timeline_.insert(timeline_.begin() + static_cast<std::ptrdiff_t>(next_change_), c);
  ++next_change_;
}

void Session::use_plugins(const PluginHost& host, std::shared_ptr<Behavior> behavior, ParameterValues params, std::uint32_t group) {
  if (behavior) {
    sim_->set_behavior(std::move(behavior), group);
    current_.groups[group].behavior.params = std::move(params);
  }
  host_ = &host;
}

std::vector<std::pair<std::string, std::string>> Session::finish() {
  try {
    return metrics_->finish(*sim_);
  } catch (const MetricFailure& e) {
    throw TestFailure(where() + ": " + e.what());
  }
}

}  // namespace salsa
