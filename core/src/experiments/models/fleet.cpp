// The fleet model: groups, batteries and failures, counted. Its settings are the drones' (battery) and the
// failures section's; it adds who is alive and the energy drawn, for the test and, with groups, each one.
#include "models.hpp"

#include "salsa/core/experiments/test_spec.hpp"
#include "salsa/core/files/csv_writer.hpp"

namespace salsa::models {
namespace {

/// One output value: a count, or a quantity written to 4 decimals (energy in Wh, time in s).
struct Value {
  double value;
  bool decimals;
};

/// alive, energy drawn (Wh) and, with return to base, time charged (s) over all drones, then found,
/// alive, energy (and time charged) of each group with several.
std::vector<Value> counts(const Simulation& sim, bool per_group, bool charging) {
  const std::size_t groups = per_group ? sim.group_count() : 0;
  std::vector<double> found(groups), alive(groups + 1), energy(groups + 1), charged(groups + 1);  // [groups]: everyone
  const auto status = sim.drone_status();
  const auto group = sim.drone_groups();
  for (std::uint32_t i = 0; i < status.size(); ++i) {
    const double joules = sim.energy_used(i), seconds = sim.charging_time(i);
    const bool flying = status[i] == DroneStatus::flying;
    alive[groups] += flying, energy[groups] += joules, charged[groups] += seconds;
    if (per_group) alive[group[i]] += flying, energy[group[i]] += joules, charged[group[i]] += seconds;
  }
  if (per_group)
    for (const TargetState& t : sim.targets())
      if (t.found()) ++found[group[t.found_by]];
  std::vector<Value> out{{alive[groups], false}, {energy[groups] / 3600, true}};
  if (charging) out.push_back({charged[groups], true});
  for (std::size_t g = 0; g < groups; ++g) {
    out.insert(out.end(), {{found[g], false}, {alive[g], false}, {energy[g] / 3600, true}});
    if (charging) out.push_back({charged[g], true});
  }
  return out;
}

}  // namespace

TestModel fleet() {
  return {
      .key = "fleet",
      .section = false,
      .meaning = "fleet: groups, batteries and failures, counted (on with several groups, a battery_capacity, a \"failures\"\n"
                 "section or a timed failure). Adds alive and energy_used_Wh to summary.csv and outcome.csv, with\n"
                 "several groups also <group>.found, <group>.alive and <group>.energy_used_Wh, and writes fleet.csv;\n"
                 "with return_to_base also charging_s (and <group>.charging_s): time spent charging.",
      .in_use = [](const TestSpec& t) { return t.fleet(); },
      .output_columns =
          [](const TestSpec& t) {
            std::vector<std::string> out;
            if (!t.fleet()) return out;
            const bool charging = t.return_to_base();
            out = {"alive", "energy_used_Wh"};
            if (charging) out.push_back("charging_s");
            if (t.groups.size() > 1)
              for (const GroupSpec& g : t.groups) {
                for (const char* column : {".found", ".alive", ".energy_used_Wh"}) out.push_back(g.name + column);
                if (charging) out.push_back(g.name + ".charging_s");
              }
            return out;
          },
      .output_values =
          [](const Simulation& sim, const TestSpec& t) {  // counts whole, energy in Wh and time in s to 4 decimals
            const std::vector<Value> values = counts(sim, t.groups.size() > 1, t.return_to_base());
            std::vector<std::string> out(values.size());
            for (std::size_t k = 0; k < values.size(); ++k) {
              if (values[k].decimals) append_number(out[k], values[k].value == 0 ? 0.0 : values[k].value, 4);
              else out[k] = std::to_string(static_cast<std::uint64_t>(values[k].value));
            }
            return out;
          },
  };
}

}  // namespace salsa::models
