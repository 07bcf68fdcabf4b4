#pragma once
// Metrics: user-defined data collection. A metric declares its columns and computes them from a
// read-only view of the world: at each logged row (columns appended to the test's summary.csv) and
// once at the end (columns appended to its outcome.csv). Calls come from the stepping thread, in order:
// reset, then step after every simulation step, observe at each logged row (every step up to that time
// has been stepped), finish once at the end.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "salsa/parameters.hpp"
#include "salsa/world.hpp"

namespace salsa {

/// One target's state.
struct TargetState {
  Vec2 position;                                                 ///< m, now (targets of a kind that moves() move)
  Vec2 found_position{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};  ///< m, where it was when found; NaN until found
  double found_time = std::numeric_limits<double>::quiet_NaN();  ///< s, end of the step it was seen in; NaN until found
  std::int64_t found_by = -1;                                    ///< drone id, -1 until found
  std::uint64_t observations = 0;  ///< drone-steps during which it was in some drone's view
  bool found() const { return found_by >= 0; }
};

/// What a metric sees: the world (drones, their properties, time, the map) plus targets and collisions.
class MetricView : public WorldView {
 public:
  virtual std::span<const TargetState> targets() const = 0;  ///< indexed by target id
  virtual std::size_t targets_found() const = 0;
  /// Contacts begun so far, drone–drone and drone–obstacle.
  virtual std::uint64_t collisions() const = 0;
};

/// A column a metric fills. Its name follows the plugin naming rule (a letter, then letters, digits,
/// '_' or '-') and must not clash with salsa's own columns or another metric's of the same test.
struct Column {
  std::string name;
  std::string unit;     ///< SI unit, or "" for a plain number or fraction
  std::string meaning;  ///< one line, for `salsa describe` and the docs
  int decimals = 6;     ///< digits after the point in the CSV files
};

/// A value that leaves its field empty (never reached, not defined); non-finite values do the same.
inline constexpr double no_value = std::numeric_limits<double>::quiet_NaN();

class Metric : public Configurable {
 public:
  /// Columns appended to summary.csv (one value each per logged row).
  virtual std::vector<Column> step_columns() const { return {}; }
  /// Columns appended to outcome.csv (one value each at the end).
  virtual std::vector<Column> final_columns() const { return {}; }
  /// The test starts: the world at time 0 (drones spawned, targets placed).
  virtual void reset(const MetricView& world) { (void)world; }
  /// After every step; for what accumulates (distance, coverage). Keep it cheap: it runs 60 times per
  /// simulated second.
  virtual void step(const MetricView& world) { (void)world; }
  /// At each logged row: one value per step column, in their order (prefilled with no_value).
  virtual void observe(const MetricView& world, std::span<double> values) { (void)world, (void)values; }
  /// At the end: one value per final column, in their order (prefilled with no_value).
  virtual void finish(const MetricView& world, std::span<double> values) { (void)world, (void)values; }
};

}  // namespace salsa
