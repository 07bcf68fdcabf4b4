#pragma once
// A model that brings its own per-drone state and its own work in the step, declared in one place
// (a test model's `simulate`, test_models.hpp) rather than written into the Simulation: its columns
// live in the simulation's column store, one row per drone id, reachable by name like the core's own
// (Simulation::columns(): drones.csv's --drone-columns, the inspector, Python); its step function runs
// once per step at its phase, serially, and may write only its own columns. The core's models that
// steer the motion itself (wind, batteries, the radio) are written into the phases instead, where they
// cost nothing when off.
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "salsa/core/model/columns.hpp"

namespace salsa {

class Simulation;

/// Where in the step a DroneModel's step function runs.
enum class ModelPhase : std::uint8_t {
  start,  ///< before the drones sense: what they will perceive and decide on this step
  moved,  ///< after the physics moved them and batteries and failures ran: the step's outcome, before it is observed
};

/// The columns of one DroneModel, owned by the simulation; rows are drone ids (removed ones included).
class ModelState {
 public:
  ModelState() = default;
  /// `declared` with data == nullptr: name, unit, meaning, type and width (the model is the DroneModel's
  /// name); each column starts at 0 for every drone, a new drone's row too.
  ModelState(std::string_view model, const std::vector<StateColumn>& declared);
  /// Rows for `drones` ids: new ones are 0.
  void grow(std::size_t drones);
  /// A column by name, as its type: std::logic_error for a name the model did not declare, or another
  /// type or width (a programming error of the model, not the user's).
  std::span<double> f64(std::string_view name);
  std::span<Vec2> vec2(std::string_view name);
  std::span<std::uint32_t> u32(std::string_view name);
  std::span<std::uint8_t> u8(std::string_view name);
  /// Its columns with their data now.
  void columns(std::vector<StateColumn>& out) const;

 private:
  struct Column {
    StateColumn declared;
    std::vector<double> f64;
    std::vector<Vec2> vec2;
    std::vector<std::uint32_t> u32;
    std::vector<std::uint8_t> u8;
  };
  Column& find(std::string_view name, StateColumn::Type type, std::size_t width);
  std::vector<Column> columns_;
};

struct DroneModel {
  std::string_view name;              ///< the columns' model ("sway"); a literal, as the columns' names
  std::vector<StateColumn> columns;   ///< declared (data == nullptr); fixed whatever the test's settings
  ModelPhase phase = ModelPhase::moved;
  /// Its work each step: reads the simulation, writes its own columns. Made from the test's settings,
  /// and made again from them when a timed change alters them (the columns keep their values).
  std::function<void(const Simulation&, ModelState&)> step;
};

}  // namespace salsa
