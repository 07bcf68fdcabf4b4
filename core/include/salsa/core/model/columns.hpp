#pragma once
// The drones' state as named columns: each model declares the arrays it keeps per drone (name, unit,
// type, meaning) once, in Simulation::columns() (core/src/model/columns.cpp), and anyone who reads the
// state by name (outputs, metrics, the inspector, Python) gets a view of the simulation's own array,
// not a copy.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace salsa {

struct StateColumn {
  enum class Type : std::uint8_t { f64, u32, u8 };
  std::string_view name;     ///< "position", "battery_left", ...
  std::string_view unit;     ///< "m", "m/s", "J", "s"; "" for a count, an id or a code
  std::string_view meaning;
  std::string_view model;    ///< who keeps it: "drone" (every test), "fleet", "wind", "sensing"
  Type type = Type::f64;
  std::size_t width = 1;     ///< values per drone: 2 for a vector (x then y)
  const void* data = nullptr;  ///< the first drone's first value; valid until the next step or live change
  std::size_t rows = 0;      ///< drones (ids, removed ones included)
  /// Bytes of one value.
  std::size_t item_size() const { return type == Type::f64 ? 8 : type == Type::u32 ? 4 : 1; }
};

}  // namespace salsa
