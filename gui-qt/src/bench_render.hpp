#pragma once
// `salsa-gui --bench-render`: frame times of the sandbox view at 1920×1080 for a swarm (random walk by
// default) over a forest with trails on (by default 1,000 drones and 50,000 trees); the frame rate and
// real-time factor while flying in real time, as the user sees them; and the simulation's speed in the
// GUI against headless (docs/gui.md).
#include <ostream>
#include <string>
#include <vector>

#include "salsa/core/plugins/plugin_host.hpp"

namespace salsa::gui {

struct BenchRenderOptions {
  int frames = 300;
  int drones = 1000;              ///< up to 10,000 on the 2 km forest; more on a map grown to keep their density
  std::string physics = "box2d";  ///< or "light" (the test field)
  std::string behavior = "random_walk";  ///< any behavior plugin, with its default parameters
  double seconds = 10;            ///< wall time of the flying measurement
  static constexpr int max_drones = 100000;
  static constexpr double min_seconds = 1, max_seconds = 600;
};

/// The benchmark's test: `drones` drones of `behavior` over 2 km × 2 km and 50,000 trees; beyond 10,000 drones
/// the map's area and the trees grow with them (10,000 drones and 50,000 trees per 4 km²) and the drones
/// start spread uniformly over it.
std::string bench_render_test(const BenchRenderOptions& options);

/// This thread's CPU time, ms: on a shared machine a frame's wall time also holds the time others had the core.
double thread_cpu_ms();

/// Mean, median, 95th percentile and largest of `times` (not empty).
struct BenchStats {
  double mean, median, p95, max;
};
BenchStats bench_stats(const std::vector<double>& times);

/// Prints the report to `out`; returns the process exit status.
int bench_render(const PluginHost& host, std::ostream& out, const BenchRenderOptions& options = {});

}  // namespace salsa::gui
