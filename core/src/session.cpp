#include "salsa/core/session.hpp"

#include "salsa/core/format.hpp"

#include <algorithm>
#include <cmath>

namespace salsa {
SummaryRow summary_row(const Simulation& sim) {
  SummaryRow row;
  row.time = sim.time();
  double sum = 0;
  for (Vec2 v : sim.drone_velocities()) {
    const double s = v.length();
    sum += s;
    row.max_speed = std::max(row.max_speed, s);
  }
  double nn_sum = 0;
  std::size_t nn_count = 0;
  for (double d : sim.nearest_neighbour_distances())
    if (std::isfinite(d)) nn_sum += d, ++nn_count;
  const std::size_t n = sim.drone_count(), targets = sim.targets().size();
  row.targets_found = sim.targets_found();
  row.fraction_found = targets ? static_cast<double>(row.targets_found) / static_cast<double>(targets) : 0.0;
  row.mean_speed = n ? sum / static_cast<double>(n) : 0.0;
  if (nn_count) row.mean_nn_distance = nn_sum / static_cast<double>(nn_count);
  row.collisions = sim.collisions();
  return row;
}

Session::Session(TestSpec test, const PluginHost& host, SessionOptions options)
    : test_(std::move(test)), current_(test_), host_(&host), timeline_(test_.changes) {
  try {
    SimulationSetup setup = make_setup(test_, host, options.threads);
    if (options.behavior) setup.behavior = std::move(options.behavior);
    sim_ = std::make_unique<Simulation>(std::move(setup));
    metrics_ = std::make_unique<MetricSet>(test_, host);
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

std::string Session::blame(const std::exception&) const {
  return "behavior '" + current_.behavior.name + "' (" + host_->behavior(current_.behavior.name).plugin().file.string() + ")";
}

bool Session::finished() const { return sim_->step_count() >= test_.steps(); }

void Session::apply_due_changes() {
  // A change applies right before the step that starts at its time.
  for (; next_change_ < timeline_.size() && change_step(timeline_[next_change_].time, sim_->dt()) <= sim_->step_count(); ++next_change_) {
    const Change& c = timeline_[next_change_];
    try {
      apply_change(*sim_, current_, c, *host_);
    } catch (const std::exception& e) {
      throw TestFailure(where() + ": the change at t = " + format::seconds(c.time) + " s could not be applied: " + e.what());
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
  } catch (const std::exception& e) {
    throw TestFailure(where() + ": " + blame(e) + " failed at t = " + format::seconds(sim_->time()) + " s: " + e.what());
  }
}

void Session::change(const std::string& key, double value) {
  const Change c{sim_->time(), key, value};
  apply_change(*sim_, current_, c, *host_);  // throws when refused, leaving both as they were
  timeline_.insert(timeline_.begin() + static_cast<std::ptrdiff_t>(next_change_), c);
  ++next_change_;
}

void Session::use_plugins(const PluginHost& host, std::shared_ptr<Behavior> behavior, ParameterValues params) {
  if (behavior) {
    sim_->set_behavior(std::move(behavior));
    current_.behavior.params = std::move(params);
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
