#pragma once
// Calling plugin code from the step: what a plugin throws becomes a PluginFailure naming its kind.
#include <cxxabi.h>

#include <cstdint>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>

#include "salsa/core/model/simulation.hpp"

namespace salsa::detail {

inline constexpr const char* behavior_kind = "behavior";
inline constexpr const char* target_kind = "target kind";
inline constexpr const char* handler_kind = "contact handler";
inline constexpr const char* wind_kind = "wind";

/// Calls plugin code: whatever it throws comes back as a PluginFailure naming the plugin (a failure
/// already named, from a nested call, passes through; so does a thread's cancellation).
template <class Fn>
decltype(auto) plugin_call(const char* kind, std::size_t index, Fn&& fn) {
  try {
    return fn();
  } catch (const PluginFailure&) {
    throw;
  } catch (const abi::__forced_unwind&) {
    throw;
  } catch (const std::exception& e) {
    throw PluginFailure(kind, index, e.what());
  } catch (...) {
    throw PluginFailure(kind, index, "an exception that is not a std::exception");
  }
}

/// Ids are 32-bit (and Box2D's user data holds id + 1).
inline void check_drone_count(std::size_t n) {
  if (n >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("drones: " + std::to_string(n) + " is too many (allowed: fewer than 4294967295)");
}

}  // namespace salsa::detail
