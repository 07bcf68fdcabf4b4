#pragma once
// The drones' state as named columns: each model keeps its per-drone arrays in a struct of its own and
// declares them (name, unit, type, meaning) once, beside the code that writes them; anyone who reads
// the state by name (outputs, metrics, the inspector, Python) gets a view of the simulation's own
// array, not a copy (Simulation::columns()).
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <vector>

#include "salsa/vec2.hpp"

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

  /// A column over `values`: a vector of double, Vec2 (two doubles, x then y), uint32, or a one-byte
  /// flag or code.
  template <class T>
  static StateColumn of(std::string_view name, std::string_view unit, std::string_view model, std::string_view meaning,
                        const std::vector<T>& values) {
    constexpr bool vector = std::is_same_v<T, Vec2>;
    static_assert(!vector || sizeof(Vec2) == 2 * sizeof(double), "a Vec2 is two doubles, x then y");
    static_assert(vector || std::is_same_v<T, double> || std::is_same_v<T, std::uint32_t> || sizeof(T) == 1);
    const Type type = std::is_same_v<T, std::uint32_t> ? Type::u32 : sizeof(T) == 1 ? Type::u8 : Type::f64;
    return {name, unit, meaning, model, type, vector ? 2u : 1u, values.data(), values.size()};
  }
};

}  // namespace salsa
