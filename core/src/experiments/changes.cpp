// Timed changes: checked against the test as it stands, applied to a running simulation between steps.
#include "salsa/core/experiments/changes.hpp"

#include <cmath>
#include <stdexcept>
#include <string_view>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {
namespace {

constexpr std::string_view params_prefix = "behavior.params.";
constexpr std::string_view drone_prefix = "drone.";
constexpr double max_drones = 1'000'000;  // as "drones" in a test file

std::string whole_in(double lo, double hi) {
  return "whole number in [" + Parameter::format(lo) + ", " + Parameter::format(hi) + "]";
}

}  // namespace

std::uint64_t change_step(double time, double dt) { return static_cast<std::uint64_t>(std::llround(time / dt)); }

std::string check_change(const TestSpec& test, const Change& c, const PluginHost& host) {
  const std::string value = Parameter::format(c.value);
  const std::string_view key = c.key;
  if (key.starts_with(params_prefix)) {
    const std::string_view name = key.substr(params_prefix.size());
    const Parameters& schema = host.behavior(test.behavior.name).factory.parameters;
    for (const Parameter& p : schema)
      if (p.name == name) {
        const std::string why = p.check(c.value);
        return why.empty() ? "" : value + " " + why;
      }
    std::string declared;
    for (const Parameter& p : schema) declared += (declared.empty() ? "" : ", ") + p.name;
    return "unknown parameter of behavior '" + test.behavior.name + "' (declared: " + (declared.empty() ? "none" : declared) + ")";
  }
  if (key == "drones") {
    if (!(c.value >= 1 && c.value <= max_drones) || c.value != std::floor(c.value))
      return value + " is out of range (allowed: " + whole_in(1, max_drones) + ")";
    return {};
  }
  if (key.starts_with(drone_prefix)) {
    const DroneProperty* property = find_drone_property(key.substr(drone_prefix.size()));
    if (!property) return "unknown drone property (allowed: " + drone_property_names() + ")";
    if (const std::string why = property->spec.check(c.value); !why.empty()) return value + " " + why;
    DroneConfig d = test.drone;
    property->set(d, c.value);
    if (const Problem p = check_drone(d, test.dt)) return p.what;
    return {};
  }
  return "unknown key (allowed: behavior.params.<name>, drones, drone.<property>)";
}

void apply_to_test(TestSpec& test, const Change& c) {
  const std::string_view key = c.key;
  if (key.starts_with(params_prefix)) test.behavior.params.set(key.substr(params_prefix.size()), c.value);
  else if (key == "drones") test.drones = static_cast<std::size_t>(c.value);
  else if (key.starts_with(drone_prefix)) find_drone_property(key.substr(drone_prefix.size()))->set(test.drone, c.value);
}

void apply_change(Simulation& sim, TestSpec& test, const Change& c, const PluginHost& host) {
  if (const std::string why = check_change(test, c, host); !why.empty()) throw std::invalid_argument(c.key + ": " + why);
  TestSpec changed = test;
  apply_to_test(changed, c);
  const std::string_view key = c.key;
  if (key.starts_with(params_prefix)) {
    const ParameterValues old = sim.behavior().parameters();
    try {
      sim.behavior().set_parameters(changed.behavior.params);
    } catch (const std::exception& e) {
      sim.behavior().set_parameters(old);  // configure() refused the combination: back to what ran
      throw PluginFailure("behavior", 0, e.what());
    } catch (...) {
      sim.behavior().set_parameters(old);
      throw PluginFailure("behavior", 0, "an exception that is not a std::exception");
    }
  } else if (key == "drones") {
    sim.set_drone_count(changed.drones);
  } else {
    sim.set_drone_config(changed.drone);
  }
  test = std::move(changed);
}

std::string refused_change(const TestSpec& test, const PluginHost& host) {
  std::shared_ptr<Behavior> behavior;  // made at the first change of a behavior parameter
  TestSpec state = test;
  for (const Change& c : test.changes) {
    apply_to_test(state, c);
    if (!std::string_view(c.key).starts_with(params_prefix)) continue;
    const Entry<Behavior>& entry = host.behavior(test.behavior.name);
    if (!behavior) behavior = PluginHost::create(entry, test.behavior.params);  // throws naming the plugin
    std::string why;
    try {
      behavior->set_parameters(state.behavior.params);
    } catch (const std::exception& e) {
      why = e.what();
    } catch (...) {
      why = "an exception that is not a std::exception";
    }
    if (why.empty()) continue;
    for (char& ch : why)
      if (ch == '\n' || ch == '\r') ch = ' ';
    std::string time = Parameter::format(c.time);
    return "changes at t = " + time + " s: " + c.key + " = " + Parameter::format(c.value) + ": behavior '" +
           test.behavior.name + "' (" + entry.plugin().file.string() + ") refused it: " + why;
  }
  return {};
}

}  // namespace salsa
