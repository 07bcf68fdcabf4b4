// What the metrics of a test cost, in isolation: record every step's drone positions from a real run
// (timing the stepping loop alone), then replay them through the test's metrics (timing only those),
// in thread CPU time, best of REPEATS each. Comparing two runs' wall times cannot resolve a few percent
// on a shared machine; this can. Build and run from the repository (after the release build):
//   g++ -std=c++20 -O2 docs/bench/metric_cost.cpp -Icore/include -Iplugin-sdk/include -Lbuild/release/lib
//       -lsalsa -Wl,-rpath,$PWD/build/release/lib -o /tmp/metric_cost
//   /tmp/metric_cost build/release/lib/salsa/plugins docs/bench/metric-cost-forest-health.json 3
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <time.h>
#include "salsa/core/experiments/test_spec.hpp"
using namespace salsa;
static double cpu() { timespec t; clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t); return t.tv_sec + 1e-9 * t.tv_nsec; }
struct Replay final : MetricView {
  const Simulation* sim; std::span<const Vec2> pos; double t = 0; DroneProperties d;
  Rect bounds() const override { return sim->bounds(); }
  double time() const override { return t; }
  double dt() const override { return sim->dt(); }
  std::span<const Vec2> drone_positions() const override { return pos; }
  std::span<const Vec2> drone_velocities() const override { return sim->drone_velocities(); }
  bool is_free(Vec2 p, double c) const override { return sim->is_free(p, c); }
  std::optional<ObstacleHit> ray_cast(Vec2 a, Vec2 b) const override { return sim->ray_cast(a, b); }
  std::span<const TargetState> targets() const override { return sim->targets(); }
  std::size_t targets_found() const override { return sim->targets_found(); }
  std::uint64_t collisions() const override { return sim->collisions(); }
  const DroneProperties& drone() const override { return d; }
  const MapData& map() const override { return sim->map(); }
};
int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: metric_cost PLUGIN_DIR TEST.json REPEATS\n");
    return 2;
  }
  PluginHost host;
  host.load({{argv[1], "x"}});
  std::ifstream in(argv[2]); std::stringstream ss; ss << in.rdbuf();
  TestSpec t = parse_test(ss.str(), "t", host);
  const int repeats = std::atoi(argv[3]);
  double sim_best = 1e9, met_best = 1e9;
  for (int rep = 0; rep < repeats; ++rep) {
    Simulation sim(make_setup(t, host, 1));
    const std::size_t n = sim.drone_count();
    std::vector<Vec2> rec(sim.drone_positions().begin(), sim.drone_positions().end());
    rec.reserve(n * (t.steps() + 1));
    double a = cpu();
    for (std::size_t i = 0; i < t.steps(); ++i) {
      sim.step();
      rec.insert(rec.end(), sim.drone_positions().begin(), sim.drone_positions().end());
    }
    sim_best = std::min(sim_best, cpu() - a);
    std::vector<std::shared_ptr<Metric>> ms;
    for (const auto& c : t.metrics) ms.push_back(PluginHost::create(host.metric(c.name), c.params));
    Replay v; v.sim = &sim; const DroneConfig& dc = sim.drone_config();
    v.d = {dc.camera_range, dc.obstacle_range, dc.detection_range, dc.max_speed, dc.max_force, dc.radius, dc.mass};
    double values[16];
    a = cpu();
    v.pos = {rec.data(), n};
    for (auto& m : ms) m->reset(v);
    for (std::size_t i = 1; i <= t.steps(); ++i) {
      v.pos = {rec.data() + i * n, n}; v.t = i * t.dt;
      for (auto& m : ms) m->step(v);
      if (i % 60 == 0) for (auto& m : ms) m->observe(v, {values, m->step_columns().size()});
    }
    for (auto& m : ms) m->finish(v, {values, m->final_columns().size()});
    met_best = std::min(met_best, cpu() - a);
  }
  std::printf("stepping %.3f s, metrics %.4f s: %.2f %% (best of %d)\n", sim_best, met_best, 100 * met_best / sim_best, repeats);
}
