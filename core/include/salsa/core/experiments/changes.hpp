#pragma once
// Timed changes: what a researcher changed while a simulation ran, as data. The GUI's sandbox sends
// every live change through apply_change and records it; a test's "changes" replays them headless at
// the same steps, so `salsa run` of a saved sandbox session gives the same data byte for byte.
// JSON (docs/test-format.md): "changes": [{"time": 30, "set": {"behavior.params.cohesion_weight": 2,
// "drones": 20}}, ...]
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/drone_config.hpp"

namespace salsa {

class PluginHost;
class Simulation;
struct TestSpec;

/// One live change: before the step that starts at `time` s, set `key` to `value`.
/// Keys: "behavior.params.<name>" (a declared parameter of the test's behavior), "drones" (drone count,
/// whole number ≥ 1), "drone.<property>" (a property of drone_schema()); with "groups", each of those
/// as "groups.<name>.<key>". "failures.drone_mtbf", "failures.camera_mtbf" (s; 0: never);
/// "comm.<field>" (a field of comm_schema(), in a test with "comm"; line_of_sight as 0 or 1). Events:
/// "fail.drone" and "fail.camera" (a drone id: it, or its camera, fails; nothing if it is down
/// already), "fail.fraction" and "fail.camera_fraction" (that share of the flying drones, chosen
/// from the seed). "wind.velocity.x", "wind.velocity.y", "wind.gusts.strength", "wind.gusts.time_scale"
/// (wind_schema()), "wind.field.params.<name>" (a declared parameter of the test's wind field).
struct Change {
  double time = 0;  ///< s; a whole number of steps: llround(time / dt) is the step it precedes
  std::string key;
  double value = 0;
  bool operator==(const Change&) const = default;
};

/// The step before which a change at `time` s is applied: llround(time / dt).
std::uint64_t change_step(double time, double dt);

/// Whether `key` takes whole numbers (a count, an id, a whole-number property): written as such.
bool change_is_whole(std::string_view key);

/// Empty when `change` may be applied to `test` as it stands (key known, value allowed by the behavior's
/// declared range, the drone configuration it makes passes check_drone), else why not, without the
/// key: "0 is out of range (allowed: whole number in [1, 1000000])".
std::string check_change(const TestSpec& test, const Change& change, const PluginHost& host);

/// Records `change` in `test` alone (its behavior parameters, drone count or drone configuration), as
/// a test that starts with the new value would hold it. Call check_change first.
void apply_to_test(TestSpec& test, const Change& change);

/// Applies `change` to `sim` at once (it takes effect in the next step) and to `test` (so later checks
/// see the new values). Throws std::invalid_argument("<key>: <why>") for a refused change, or what the
/// plugin's configure() or the simulation throws; either way `sim` and `test` are left as they were.
void apply_change(Simulation& sim, TestSpec& test, const Change& change, const PluginHost& host);

/// The timed changes applied as a run will apply them, short of running: a behavior made with the
/// test's parameters gets each behavior.params change in order through set_parameters, so what its
/// configure() refuses is found before the run. Empty, or the first refusal on one line: "changes at
/// t = 1 s: behavior.params.k = 5: behavior 'b' (/path/libb.so) refused it: <its message>". Call
/// after each change passed check_change.
std::string refused_change(const TestSpec& test, const PluginHost& host);

}  // namespace salsa
