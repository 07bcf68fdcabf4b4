#pragma once
// Benchmark workloads (defined in docs/benchmarks.md) and the bare-Box2D floor they are compared with.
#include <cstddef>
#include <cstdint>
#include <string>

#include "salsa/core/plugins/plugin_host.hpp"
#include "salsa/core/model/simulation.hpp"

namespace salsa::bench {

struct Workload {
  std::size_t drones = 100;
  std::size_t targets = 1000;
  double side = 2000;                    ///< m, square map closed by four walls
  Vec2 spawn{924.55, 950.54};            ///< m
  SpawnMode spawn_mode = SpawnMode::disc;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string behavior = "flocking";     ///< flocking with the paper's parameters, any other with its defaults
  bool fleet = false;                    ///< two groups, batteries and failure rates on (the fleet model's cost)
  bool wind = false;                     ///< a 3 m/s wind with gusts of 1 m/s (τ 10 s) (the wind model's cost)
  /// > 0: the comm model on with this range (m) and line of sight, and every drone broadcasting its
  /// position and velocity every step (and summing what it receives): the comm model's cost.
  double comm_range = 0;
  PhysicsMode physics = PhysicsMode::box2d;  ///< light: salsa's own physics instead of Box2D
  /// A pile: half the swarm twice the radius (four times the mass), all spawned packed in the smallest
  /// disc around the spawn point that holds their bodies (the densest the room check lets through) and
  /// flying at max speed to that point, instead of the behavior: the physics' densest work (in light
  /// mode, the extra passes of a pile of two sizes).
  bool pile = false;
};

/// Table I: flocking with the paper's parameters (or `w.behavior` with its defaults), "small" drones, trees of radius 5 m, summary every
/// 50 steps. Needs the flocking, tree and detect_targets plugins.
SimulationSetup table1(const PluginHost& host, const Workload& w);

/// Constant density for `drones` drones: the Table I density (1,000 drones on 2 km × 2 km), 10 targets
/// per drone, spawned uniformly (a disc of N m would not fit the map at 100,000 drones).
Workload scale(std::size_t drones, std::uint64_t seed, int threads);

/// The ABM frameworks' flocking model (JuliaDynamics/ABMFrameworksComparison), as
/// examples/abm-flocking-small.json and -large.json run it: `abm_flocking` with its defaults, light
/// physics, one step of 1 s per step of theirs, drones of radius 1 m (the least a step of 1 m allows)
/// spawned uniformly, no targets, obstacle rays or metrics. Small: 200 birds on 100 m × 100 m,
/// visual distance 5 m; large: 400 on 150 m × 150 m, 15 m. Needs the abm_flocking plugin.
SimulationSetup abm_flocking(const PluginHost& host, bool large, std::uint64_t seed);

/// The Box2D floor of a run: the same walls, bodies, spawn and Box2D settings stepped in a bare Box2D
/// world, each body given every step the velocity salsa commanded for it in that step (recorded during
/// the run), with no sensing, behaviors or targets. So the floor moves exactly the same bodies the same
/// way, and the difference is salsa's own cost.
class Floor {
 public:
  /// Room for `steps` steps of `drones` drones (float pairs), reserved up front.
  Floor(std::size_t drones, std::size_t steps);
  /// Call after each step of the run.
  void record(const Simulation& sim);
  /// Seconds to replay the recorded steps (wall clock, or this process's CPU clock with `cpu`).
  double replay_seconds(const SimulationSetup& setup, bool cpu = false) const;
  std::size_t bytes() const { return commands_.capacity() * sizeof(float); }

 private:
  std::size_t drones_;
  std::vector<float> commands_;
};

/// Seconds on the wall clock, or with `cpu` on this process's CPU clock: on a shared machine the CPU
/// clock leaves out the time other processes had the core (single-threaded runs only).
double seconds_now(bool cpu);

/// Peak resident memory of this process since the last reset (bytes); reset works on Linux ≥ 4.0.
std::size_t peak_rss_bytes();
void reset_peak_rss();

}  // namespace salsa::bench
