// The comm model: messages between drones ("comm": {...}), and their counters in the data files.
#include "models.hpp"

#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::models {

TestModel comm() {
  return {
      .key = "comm",
      .meaning = "comm: a test's communication model (\"comm\": {...}; absent: drones exchange no messages). Timed changes\n"
                 "and sweeps set its fields as comm.<field>; line_of_sight is true or false (1 or 0 in changes and sweeps).\n"
                 "Loss at distance d: p = 1 - (1 - loss)(1 - loss_at_range (d / range)^2).",
      .fields = bound_fields<&TestSpec::comm>(comm_schema()),
      .in_use = [](const TestSpec& t) { return t.comm.on; },
      .given = [](TestSpec& t) { t.comm.on = true; },
      .changes_while_off = false,
      .apply = [](Simulation& sim, const TestSpec& t) { sim.set_comm(t.comm); },
      .output_columns = [](const TestSpec& t) { return t.comm.on ? std::vector<std::string>(std::begin(comm_columns), std::end(comm_columns)) : std::vector<std::string>{}; },
      .output_values =
          [](const Simulation& sim, const TestSpec&) {
            const CommCounters& c = sim.comm_counters();
            std::vector<std::string> out;
            for (std::uint64_t v : {c.sent, c.delivered, c.dropped_range, c.dropped_obstacle, c.dropped_loss, c.dropped_cap})
              out.push_back(std::to_string(v));
            return out;
          },
  };
}

}  // namespace salsa::models
