// Timed changes: checked against the test as it stands, applied to a running simulation between steps.
#include "salsa/core/experiments/changes.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"
#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/experiments/test_spec.hpp"

namespace salsa {
namespace {

constexpr std::string_view groups_prefix = "groups.";
constexpr std::string_view params_prefix = "behavior.params.";
constexpr std::string_view drone_prefix = "drone.";
constexpr std::string_view wind_params_prefix = "wind.field.params.";
constexpr double max_id = 4294967294.0;   // ids are 32-bit

std::string whole_in(double lo, double hi) {
  return "whole number in [" + Parameter::format(lo) + ", " + Parameter::format(hi) + "]";
}

/// A key split into the group it addresses and the rest ("groups.scouts.drones" → scouts, "drones").
/// Keys of no group (failures, fail events) have group -1.
struct Target {
  int group = -1;
  std::string_view rest;
  std::string problem;  ///< why the key names no group it should
};
bool of_a_group(std::string_view rest) {
  return rest == "drones" || rest.starts_with(params_prefix) || rest.starts_with(drone_prefix);
}
std::string group_names(const TestSpec& test) {
  std::string out;
  for (const GroupSpec& g : test.groups) out += (out.empty() ? "" : ", ") + g.name;
  return out;
}
Target target(const TestSpec& test, std::string_view key) {
  if (key.starts_with(groups_prefix)) {
    const std::string_view tail = key.substr(groups_prefix.size());
    const auto dot = tail.find('.');
    const std::string_view name = tail.substr(0, dot);
    const int g = test.group_index(name);
    if (g < 0) return {-1, {}, "unknown group '" + std::string(name) + "' (groups: " + group_names(test) + ")"};
    if (dot == std::string_view::npos || !of_a_group(tail.substr(dot + 1)))
      return {-1, {}, "unknown key (allowed: groups.<name>.drones, groups.<name>.drone.<property>, groups.<name>.behavior.params.<name>)"};
    return {g, tail.substr(dot + 1), {}};
  }
  if (!of_a_group(key)) return {-1, key, {}};
  if (test.groups.size() > 1)
    return {-1, {}, "the test has " + std::to_string(test.groups.size()) + " groups: say whose, groups.<name>." + std::string(key) +
                        " (groups: " + group_names(test) + ")"};
  return {0, key, {}};
}

/// `v` (shown as `value`) for parameter `name` of a plugin's declared `schema`: "" when allowed, else why
/// (out of range, or unknown, listing what `plugin` declares).
std::string check_param(const Parameters& schema, std::string_view name, double v, const std::string& value, const std::string& plugin) {
  for (const Parameter& p : schema)
    if (p.name == name) {
      const std::string why = p.check(v);
      return why.empty() ? "" : value + " " + why;
    }
  std::string declared;
  for (const Parameter& p : schema) declared += (declared.empty() ? "" : ", ") + p.name;
  return "unknown parameter of " + plugin + " (declared: " + (declared.empty() ? "none" : declared) + ")";
}

/// "wind.velocity.x, wind.velocity.y, ..., wind.field.params.<name>": a model's keys, for messages.
std::string model_keys(const TestModel& m) {
  std::string out;
  for (const ModelField& f : m.fields) out += (out.empty() ? "" : ", ") + m.key + "." + f.spec.name;
  return out + (m.other_forms.empty() ? "" : ", " + m.other_forms);
}

}  // namespace

std::uint64_t change_step(double time, double dt) { return static_cast<std::uint64_t>(std::llround(time / dt)); }

bool change_is_whole(std::string_view key) {
  if (key == "drones" || key.ends_with(".drones") || key == "fail.drone" || key == "fail.camera") return true;
  if (const TestModel* m = model_of_key(key)) {
    const ModelField* f = m->find(key.substr(m->key.size() + 1));
    return f && f->spec.is_integer();
  }
  const auto at = key.rfind(drone_prefix);
  const DroneProperty* p = at != std::string_view::npos ? drone_schema().find(key.substr(at + drone_prefix.size())) : nullptr;
  return p && p->spec.is_integer();
}

std::string check_change(const TestSpec& test, const Change& c, const PluginHost& host) {
  const std::string value = Parameter::format(c.value);
  const Target to = target(test, c.key);
  if (!to.problem.empty()) return to.problem;
  const std::string_view key = to.rest;
  if (to.group >= 0) {
    const GroupSpec& g = test.groups[static_cast<std::size_t>(to.group)];
    if (key.starts_with(params_prefix)) {
      return check_param(host.behavior(g.behavior.name).factory.parameters, key.substr(params_prefix.size()), c.value, value,
                         "behavior '" + g.behavior.name + "'");
    }
    if (key == "drones") {
      constexpr auto most = static_cast<double>(max_test_drones);
      if (!(c.value >= 1 && c.value <= most) || c.value != std::floor(c.value))
        return value + " is out of range (allowed: " + whole_in(1, most) + ")";
      const double others = static_cast<double>(test.drone_total() - g.drones);
      if (others + c.value > most)
        return value + " drones and " + Parameter::format(others) + " in the other groups make " + Parameter::format(others + c.value) +
               " (allowed: at most " + Parameter::format(most) + " drones in a test, over all its groups)";
      return {};
    }
    const DroneProperty* property = drone_schema().find(key.substr(drone_prefix.size()));
    if (!property) return "unknown drone property (allowed: " + drone_schema().names() + ")";
    if (const std::string why = property->spec.check(c.value); !why.empty()) return value + " " + why;
    DroneConfig d = g.drone;
    property->set(d, c.value);
    if (const Problem p = check_drone(d, test.dt)) return p.what;
    if (const Problem p = check_wind(test.wind, d, test.dt)) return p.field + ": " + p.what;
    return {};
  }
  if (key.starts_with(wind_params_prefix)) {
    if (test.wind_field.name.empty()) return "the test has no wind field (allowed: wind.field.params.<name> with a \"wind\": {\"field\": ...})";
    return check_param(host.wind(test.wind_field.name).factory.parameters, key.substr(wind_params_prefix.size()), c.value, value,
                       "wind '" + test.wind_field.name + "'");
  }
  if (const TestModel* m = model_of_key(key)) {
    const ModelField* f = m->find(key.substr(m->key.size() + 1));
    if (!f) return "unknown key (allowed: " + model_keys(*m) + ")";
    if (!m->changes_while_off && !m->in_use(test))
      return "the test has no \"" + m->key + "\" (allowed: " + m->key + ".<field> in a test with a \"" + m->key + "\" object; \"" + m->key +
             "\": {} gives the defaults)";
    if (const std::string why = f->spec.check(c.value); !why.empty()) return value + " " + why;
    if (!m->problem) return {};
    TestSpec changed = test;
    f->set(changed, c.value);
    return m->problem(changed);
  }
  if (key == "fail.drone" || key == "fail.camera") {
    if (!(c.value >= 0 && c.value <= max_id) || c.value != std::floor(c.value))
      return value + " is out of range (allowed: a drone id, " + whole_in(0, max_id) + ")";
    return {};
  }
  if (key == "fail.fraction" || key == "fail.camera_fraction") {
    if (!(c.value >= 0 && c.value <= 1)) return value + " is out of range (allowed: a fraction in [0, 1])";
    return {};
  }
  std::string models;
  for (const TestModel& m : test_models())
    if (m.section) models += m.key + ".<" + m.names() + ">, " + (m.other_forms.empty() ? "" : m.other_forms + ", ");
  return "unknown key (allowed: behavior.params.<name>, drones, drone.<property>, groups.<name>.<any of those>, " + models +
         "fail.drone, fail.camera, fail.fraction, fail.camera_fraction)";
}

void apply_to_test(TestSpec& test, const Change& c) {
  const Target to = target(test, c.key);
  const std::string_view key = to.rest;
  if (to.group >= 0) {
    GroupSpec& g = test.groups[static_cast<std::size_t>(to.group)];
    if (key.starts_with(params_prefix)) g.behavior.params.set(key.substr(params_prefix.size()), c.value);
    else if (key == "drones") g.drones = static_cast<std::size_t>(c.value);
    else drone_schema().find(key.substr(drone_prefix.size()))->set(g.drone, c.value);
  } else if (key.starts_with(wind_params_prefix)) {
    test.wind_field.params.set(key.substr(wind_params_prefix.size()), c.value);
  } else if (const TestModel* m = model_of_key(key)) {
    m->find(key.substr(m->key.size() + 1))->set(test, c.value);
  }  // fail.*: events, nothing the test holds
}

void apply_change(Simulation& sim, TestSpec& test, const Change& c, const PluginHost& host) {
  if (const std::string why = check_change(test, c, host); !why.empty()) throw std::invalid_argument(c.key + ": " + why);
  TestSpec changed = test;
  apply_to_test(changed, c);
  const Target to = target(test, c.key);
  const std::string_view key = to.rest;
  const auto g = static_cast<std::uint32_t>(std::max(to.group, 0));
  if (to.group >= 0 && key.starts_with(params_prefix)) {
    Behavior& behavior = sim.behavior(g);
    const ParameterValues old = behavior.parameters();
    try {
      behavior.set_parameters(changed.groups[g].behavior.params);
    } catch (const std::exception& e) {
      behavior.set_parameters(old);  // configure() refused the combination: back to what ran
      throw PluginFailure("behavior", g, e.what());
    } catch (...) {
      behavior.set_parameters(old);
      throw PluginFailure("behavior", g, "an exception that is not a std::exception");
    }
  } else if (to.group >= 0 && key == "drones") {
    sim.set_drone_count(changed.groups[g].drones, g);
  } else if (to.group >= 0) {
    sim.set_drone_config(changed.groups[g].drone, g);
  } else if (key.starts_with(wind_params_prefix)) {
    WindField& field = *sim.wind_field_ptr();
    const ParameterValues old = field.parameters();
    try {
      field.set_parameters(changed.wind_field.params);
    } catch (const std::exception& e) {
      field.set_parameters(old);  // configure() refused the combination: back to what ran
      throw PluginFailure("wind", 0, e.what());
    } catch (...) {
      field.set_parameters(old);
      throw PluginFailure("wind", 0, "an exception that is not a std::exception");
    }
  } else if (const TestModel* m = model_of_key(key)) {
    if (m->apply) m->apply(sim, changed);
    if (m->simulate) sim.set_model(m->simulate(changed));
  } else if (key == "fail.drone" || key == "fail.camera") {
    try {
      sim.fail(static_cast<std::uint32_t>(c.value), key == "fail.camera");
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(c.key + ": " + e.what());
    }
  } else {
    sim.fail_fraction(c.value, key == "fail.camera_fraction");
  }
  test = std::move(changed);
}

std::string refused_change(const TestSpec& test, const PluginHost& host) {
  std::vector<std::shared_ptr<Behavior>> behaviors(test.groups.size());  // each made at its group's first parameter change
  std::shared_ptr<WindField> field;                                      // made at the field's first
  auto refusal = [](Configurable& plugin, const ParameterValues& values) {
    std::string why;
    try {
      plugin.set_parameters(values);
    } catch (const std::exception& e) {
      why = e.what();
    } catch (...) {
      why = "an exception that is not a std::exception";
    }
    for (char& ch : why)
      if (ch == '\n' || ch == '\r') ch = ' ';
    return why;
  };
  auto line = [](const Change& c, const std::string& plugin, const fs::path& file, const std::string& why) {
    return "changes at t = " + Parameter::format(c.time) + " s: " + c.key + " = " + Parameter::format(c.value) + ": " + plugin + " (" +
           file.string() + ") refused it: " + why;
  };
  TestSpec state = test;
  for (const Change& c : test.changes) {
    apply_to_test(state, c);
    if (c.key.starts_with(wind_params_prefix)) {
      const Entry<WindField>& entry = host.wind(test.wind_field.name);
      if (!field) field = PluginHost::create(entry, test.wind_field.params);  // throws naming the plugin
      if (std::string why = refusal(*field, state.wind_field.params); !why.empty())
        return line(c, "wind '" + test.wind_field.name + "'", entry.plugin().file, why);
      continue;
    }
    const Target to = target(test, c.key);
    if (to.group < 0 || !to.rest.starts_with(params_prefix)) continue;
    const auto g = static_cast<std::size_t>(to.group);
    const Entry<Behavior>& entry = host.behavior(test.groups[g].behavior.name);
    if (!behaviors[g]) behaviors[g] = PluginHost::create(entry, test.groups[g].behavior.params);  // throws naming the plugin
    if (std::string why = refusal(*behaviors[g], state.groups[g].behavior.params); !why.empty())
      return line(c, "behavior '" + test.groups[g].behavior.name + "'", entry.plugin().file, why);
  }
  return {};
}

}  // namespace salsa
