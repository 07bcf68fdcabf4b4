#pragma once
// The random streams of a test's seed, in one place: which stream each use draws from decides what
// stays paired between the behaviors of a repeat (the world, spawns, failures, noise), so no two uses
// may share one.
#include <cstdint>

#include "salsa/rng.hpp"

namespace salsa::detail {

// Rng streams: a few fixed ones for set-up, the wind's gusts and the targets' motion, then one per drone.
constexpr std::uint64_t targets_stream = 1, spawn_stream = 2, gust_stream = 3, target_motion_stream = 4, first_drone_stream = 16;
/// A drone's failure draws: Exp(1) for the whole drone, then for its camera, from its own stream.
constexpr std::uint64_t first_failure_stream = std::uint64_t{1} << 40;

/// Sensor noise draws from counter-based streams, one per (purpose, step, drone), never the behavior's:
/// any thread count, any order of the drones and every behavior of a repeat draw the same noise, and
/// one purpose's draws never shift another's. Bit 63 sets the family apart from the streams above;
/// bits 61-62 hold the purpose, 32-60 the step (the same draws come back after 2^29 steps, 103 days of
/// simulated time at 60 steps a second), 0-31 the drone id.
enum class NoiseStream : std::uint64_t { position_and_rays = 0, neighbours = 1, misses = 2, phantoms = 3 };
inline Rng noise_rng(std::uint64_t seed, NoiseStream purpose, std::uint64_t step, std::uint32_t id) {
  constexpr std::uint64_t first_noise_stream = std::uint64_t{1} << 63, step_mask = (std::uint64_t{1} << 29) - 1;
  return Rng(seed, first_noise_stream | static_cast<std::uint64_t>(purpose) << 61 | (step & step_mask) << 32 | id);
}

}  // namespace salsa::detail
