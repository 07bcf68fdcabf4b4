#pragma once
// A plugin's test fixture: a small real simulation, the same core `salsa run` uses, stepped by the
// test. Link `salsa::fixture` (libsalsa). For a quick unit check of one `decide`, salsa/testing.hpp's
// Scene needs no library.
//
//   salsa::testing::Simulation sim(R"({"behavior": "levy_walk", "drones": 8, "targets": 20, "seed": 3})",
//                                  {LEVY_WALK_FILE});   // the plugin file your build made
//   sim.run(30);                                         // 30 s simulated
//   CHECK(sim.targets_found() > 0);
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "salsa/behavior.hpp"
#include "salsa/world.hpp"

namespace salsa::testing {

class Simulation {
 public:
  /// `test`: one test as in a test file (JSON text: behavior, drones, map, targets, seed, metrics...;
  /// "time" is ignored, the test steps). `plugins`: plugin files or folders loaded before salsa's own
  /// built-in plugins (a name in both is yours). Nothing else is searched (not the user folder), so a
  /// test sees the same plugins on every machine. Throws std::runtime_error with `salsa run`'s message
  /// for bad input.
  explicit Simulation(const std::string& test, const std::vector<std::string>& plugins = {});
  /// The same test with `behavior` instead of the test's "behavior" (which may then be left out): test
  /// a class directly. One without parameter values gets its Param members' defaults.
  Simulation(std::shared_ptr<Behavior> behavior, const std::string& test, const std::vector<std::string>& plugins = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// One step of dt (sense, decide, act, physics, detect, observe) through the run loop `salsa run` uses:
  /// the test's timed changes apply, metrics step. Throws std::runtime_error naming the plugin that failed.
  void step();
  void run(double seconds);  ///< steps until `seconds` more have been simulated (whole steps)

  double time() const;                    ///< s simulated
  const WorldView& world() const;         ///< bounds, drone positions and velocities, map, is_free...
  std::span<const Vec2> positions() const { return world().drone_positions(); }  ///< m, by drone id
  std::span<const Vec2> velocities() const { return world().drone_velocities(); }  ///< m/s, by drone id
  std::size_t targets() const;            ///< targets placed
  std::size_t targets_found() const;
  std::vector<Vec2> target_positions() const;
  Behavior& behavior() const;             ///< the running behavior (its inspect(id) text, say)
  /// A metric column's value now (e.g. "coverage" of area_coverage; the test's "metrics", or salsa's
  /// default metrics when it names none). Throws std::out_of_range for an unknown column.
  double metric(const std::string& column) const;
  std::vector<std::string> metric_columns() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace salsa::testing
