// The column store of models declared outside the Simulation (drone_model.hpp), and their turn in the step.
#include "salsa/core/model/drone_model.hpp"

#include <stdexcept>
#include <string>

#include "salsa/core/model/simulation.hpp"

namespace salsa {

ModelState::ModelState(std::string_view model, const std::vector<StateColumn>& declared) {
  for (StateColumn c : declared) {
    if (c.width != 1 && !(c.width == 2 && c.type == StateColumn::Type::f64))
      throw std::logic_error(std::string(model) + "." + std::string(c.name) + ": a column is one value or an (x, y) of doubles per drone");
    c.model = model;
    c.data = nullptr;
    c.rows = 0;
    columns_.push_back({c, {}, {}, {}, {}});
  }
}

void ModelState::grow(std::size_t drones) {
  for (Column& c : columns_) {
    if (c.declared.width == 2) c.vec2.resize(drones);
    else if (c.declared.type == StateColumn::Type::f64) c.f64.resize(drones, 0.0);
    else if (c.declared.type == StateColumn::Type::u32) c.u32.resize(drones, 0);
    else c.u8.resize(drones, 0);
  }
}

ModelState::Column& ModelState::find(std::string_view name, StateColumn::Type type, std::size_t width) {
  for (Column& c : columns_)
    if (c.declared.name == name) {
      if (c.declared.type != type || c.declared.width != width)
        throw std::logic_error(std::string(c.declared.model) + "." + std::string(name) + ": read as another type than declared");
      return c;
    }
  throw std::logic_error("model column " + std::string(name) + ": not declared by its model");
}

std::span<double> ModelState::f64(std::string_view name) { return find(name, StateColumn::Type::f64, 1).f64; }
std::span<Vec2> ModelState::vec2(std::string_view name) { return find(name, StateColumn::Type::f64, 2).vec2; }
std::span<std::uint32_t> ModelState::u32(std::string_view name) { return find(name, StateColumn::Type::u32, 1).u32; }
std::span<std::uint8_t> ModelState::u8(std::string_view name) { return find(name, StateColumn::Type::u8, 1).u8; }

void ModelState::columns(std::vector<StateColumn>& out) const {
  for (const Column& c : columns_) {
    const StateColumn& d = c.declared;
    if (d.width == 2) out.push_back(StateColumn::of(d.name, d.unit, d.model, d.meaning, c.vec2));
    else if (d.type == StateColumn::Type::f64) out.push_back(StateColumn::of(d.name, d.unit, d.model, d.meaning, c.f64));
    else if (d.type == StateColumn::Type::u32) out.push_back(StateColumn::of(d.name, d.unit, d.model, d.meaning, c.u32));
    else out.push_back(StateColumn::of(d.name, d.unit, d.model, d.meaning, c.u8));
  }
}

void Simulation::run_models(ModelPhase phase) {
  for (std::size_t k = 0; k < setup_.models.size(); ++k)
    if (setup_.models[k].phase == phase) setup_.models[k].step(*this, drones_.models[k]);
}

void Simulation::set_model(DroneModel model) {
  for (DroneModel& m : setup_.models)
    if (m.name == model.name) {
      m.step = std::move(model.step);
      return;
    }
  drones_.models.emplace_back(model.name, model.columns);
  drones_.models.back().grow(drones_.positions.size());
  setup_.models.push_back(std::move(model));
}

}  // namespace salsa
