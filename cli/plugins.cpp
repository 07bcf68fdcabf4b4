// salsa plugins (what was found, where, and what was refused) and salsa describe NAME (a plugin's
// parameters and, for a metric, its columns).
#include <array>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <type_traits>

#include "salsa/core/experiments/test_models.hpp"
#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/plugins/plugin_host.hpp"
#include "commands.hpp"
#include "options.hpp"

namespace fs = std::filesystem;
using namespace salsa;
using namespace salsa::cli;

int cmd_plugins(int argc, char** argv) {
  po::variables_map vm;
  if (!parse(argc, argv, "plugins", "[options]", po::options_description("plugins options"), vm, plugin_options)) return 0;
  PluginHost host;
  load_plugins(host, vm, false);
  std::cout << "Folders searched, in order:\n";
  std::error_code ec;  // a link loop is "missing" here; the Refused list below says why
  for (const auto& d : host.searched())
    std::cout << "  " << std::left << std::setw(18) << d.origin << " " << d.path.string()
              << (fs::is_directory(d.path, ec) ? "" : "  (missing)") << "\n";
  // Columns as wide as their longest entry.
  std::vector<std::array<std::string, 5>> rows{{"KIND", "NAME", "VERSION", "BRIEF", "FILE"}};
  auto add = [&](const char* kind, const auto& entries) {
    for (const auto& e : entries)
      rows.push_back({kind, e.factory.name, e.plugin().version, e.factory.brief, e.plugin().file.string()});
  };
  add("behavior", host.behaviors());
  add("target", host.target_kinds());
  add("map", host.maps());
  add("contact handler", host.contact_handlers());
  add("metric", host.metrics());
  add("wind", host.winds());
  std::array<std::size_t, 5> width{};
  for (const auto& r : rows)
    for (std::size_t c = 0; c < r.size(); ++c) width[c] = std::max(width[c], r[c].size());
  std::cout << "\nPlugins:\n";
  for (const auto& r : rows) {
    std::cout << " ";
    for (std::size_t c = 0; c < r.size(); ++c) std::cout << " " << std::left << std::setw(c + 1 < r.size() ? int(width[c]) : 0) << r[c];
    std::cout << "\n";
  }
  if (!host.failures().empty()) {
    std::cout << "\nRefused:\n";
    for (const auto& f : host.failures()) std::cout << "  " << f.file.string() << ": " << f.reason << "\n";
  }
  return 0;
}

namespace {

/// A metric's columns with its default parameters (they may depend on the parameters).
void describe_columns(const Entry<Metric>& e) {
  std::shared_ptr<Metric> metric;
  std::vector<Column> step, final;
  try {
    metric = PluginHost::create(e, ParameterValues(e.factory.parameters));
    step = metric->step_columns();
    final = metric->final_columns();
  } catch (const std::exception& x) {
    std::cout << "  columns cannot be listed: " << x.what() << "\n\n";
    return;
  }
  std::cout << "  " << std::left << std::setw(28) << "COLUMN" << std::setw(20) << "FILE" << std::setw(8) << "UNIT" << "MEANING\n";
  for (auto [file, columns] : {std::pair{"summary.csv", &step}, {"outcome.csv", &final}})
    for (const Column& c : *columns)
      std::cout << "  " << std::setw(28) << c.name << std::setw(20) << file << std::setw(8) << (c.unit.empty() ? "-" : c.unit)
                << c.meaning << "\n";
  std::cout << "\n";
}

}  // namespace

int cmd_describe(int argc, char** argv) {
  po::options_description o("describe options");
  std::string models;
  for (const TestModel& m : test_models()) models += ", " + m.key;
  const std::string help = "plugin name (behavior, target kind, map, contact handler, metric or wind field), or drone" + models + ", columns";
  o.add_options()("name", po::value<std::string>(), help.c_str());
  po::variables_map vm;
  if (!parse(argc, argv, "describe", "NAME [options]", o, vm, plugin_options, positional("name"))) return 0;
  if (!vm.count("name")) throw InputError("describe: missing NAME (see 'salsa plugins' for the names)");
  const std::string name = vm["name"].as<std::string>();
  auto table = [](const Parameters& parameters) {
    std::cout << "  " << std::left << std::setw(28) << "PARAMETER" << std::setw(10) << "DEFAULT" << std::setw(10) << "MIN"
              << std::setw(12) << "MAX" << std::setw(14) << "UNIT" << "MEANING\n";
    for (const auto& p : parameters)
      std::cout << "  " << std::setw(28) << p.name << std::setw(10) << Parameter::format(p.value) << std::setw(10)
                << Parameter::format(p.min) << std::setw(12) << Parameter::format(p.max) << std::setw(14)
                << (p.unit.empty() ? "-" : p.unit) << p.description << (p.is_integer() ? " (whole number)" : "") << "\n";
  };
  if (name == "drone") {  // not a plugin: the drone properties every test has (drone_schema)
    std::cout << "drone: the properties of a test's \"drone\" (or a group's; defaults: the \"small\" drone); timed changes\n"
                 "set them as drone.<property> (groups.<name>.drone.<property>). The battery and power model (Zeng, Xu &\n"
                 "Zhang 2019) are off while battery_capacity is 0; sensor noise is off while its five properties are 0.\n\n";
    Parameters specs;
    for (const DroneProperty& p : drone_schema()) specs.push_back(p.spec);
    table(specs);
    std::cout << "\n  named configurations (\"drone\": \"NAME\", or {\"base\": \"NAME\", ...}):\n";
    for (const DroneConfig& c : builtin_drone_configs()) {
      std::cout << "  " << std::setw(8) << c.name;
      for (const DroneProperty& p : drone_schema())  // the energy model's and noise only where a configuration sets them
        if (p.section == DroneSection::body || p.get(c) != p.spec.value) std::cout << " " << p.spec.name << "=" << Parameter::format(p.get(c));
      std::cout << "\n";
    }
    return 0;
  }
  if (name == "columns") {  // the drones' state by name: what --drone-columns and the Python package read
    std::cout << "columns: each drone's state, one column per quantity, kept by the model named (the wind's once a test\n"
                 "has had wind). salsa run --drone-columns NAME,... adds them to drones.csv (a vector as NAME_x, NAME_y)\n"
                 "and to trajectories.nc (--archive), which holds position, velocity, group, status, status_since, camera_works,\n"
                 "energy_used, battery_left, errand and charging_time without them.\n\n";
    std::cout << "  " << std::left << std::setw(26) << "COLUMN" << std::setw(8) << "UNIT" << std::setw(10) << "MODEL" << std::setw(9) << "VALUES" << "MEANING\n";
    for (const StateColumn& c : declared_drone_columns()) {
      const char* type = c.type == StateColumn::Type::f64 ? (c.width == 2 ? "2 x f64" : "f64") : c.type == StateColumn::Type::u32 ? "u32" : "u8";
      std::cout << "  " << std::setw(26) << std::string(c.name) << std::setw(8) << std::string(c.unit) << std::setw(10) << std::string(c.model)
                << std::setw(9) << type << c.meaning << "\n";
    }
    return 0;
  }
  // A test's models with no plugin behind them (test_models.hpp): what the model is, then its settings;
  // the wind also lists the fields that can join it.
  for (const TestModel& m : test_models()) {
    if (m.key != name) continue;
    std::cout << m.meaning << "\n\n";
    Parameters specs;
    for (const ModelField& f : m.fields) specs.push_back(f.spec);
    if (!specs.empty()) table(specs);  // a model without a section has its settings among the drone's
    if (name == "wind") {
      PluginHost host;
      load_plugins(host, vm, true);
      std::cout << "\n  wind fields (\"field\": \"NAME\"; salsa describe NAME lists its parameters):";
      for (const auto& e : host.winds()) std::cout << " " << e.factory.name;
      std::cout << (host.winds().empty() ? " none loaded\n" : "\n");
    }
    return 0;
  }
  PluginHost host;
  load_plugins(host, vm, true);
  bool found = false;
  auto describe = [&](const char* kind, const auto& entries) {
    for (const auto& e : entries) {
      if (e.factory.name != name) continue;
      found = true;
      std::cout << kind << " '" << name << "': " << e.factory.brief << "\n  from " << e.plugin().file.string()
                << " (plugin " << e.plugin().name << " " << e.plugin().version << ")\n\n";
      if constexpr (std::is_same_v<std::decay_t<decltype(e)>, Entry<Metric>>) describe_columns(e);
      if (e.factory.parameters.empty()) {
        std::cout << "  no parameters\n";
        continue;
      }
      table(e.factory.parameters);
    }
  };
  describe("behavior", host.behaviors());
  describe("target kind", host.target_kinds());
  describe("map", host.maps());
  describe("contact handler", host.contact_handlers());
  describe("metric", host.metrics());
  describe("wind", host.winds());
  if (!found) throw InputError("describe: no plugin named '" + name + "' (see 'salsa plugins')");
  return 0;
}

