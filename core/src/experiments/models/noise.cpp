// The sensor noise model: its settings are the drones' (position_noise ... false_detection_rate); it adds
// the count of false detections while any drone can make one.
#include "models.hpp"

#include "salsa/core/experiments/test_spec.hpp"

namespace salsa::models {
namespace {

bool counts_false_detections(const TestSpec& test) {
  for (const GroupSpec& g : test.groups)
    if (g.drone.false_detection_rate > 0) return true;
  for (const Change& c : test.changes)
    if (c.key.ends_with("drone.false_detection_rate") && c.value > 0) return true;
  return false;
}

}  // namespace

TestModel noise() {
  return {
      .key = "noise",
      .section = false,
      .meaning = "noise: the drones' sensor noise (drone properties position_noise, neighbour_noise, obstacle_noise,\n"
                 "miss_probability, false_detection_rate; all 0: off). With a false_detection_rate (or a timed change to\n"
                 "one) summary.csv and outcome.csv count false_detections.",
      .in_use = counts_false_detections,
      .output_columns = [](const TestSpec& t) { return counts_false_detections(t) ? std::vector<std::string>{"false_detections"} : std::vector<std::string>{}; },
      .output_values = [](const Simulation& sim, const TestSpec&) { return std::vector<std::string>{std::to_string(sim.false_detections())}; },
  };
}

}  // namespace salsa::models
