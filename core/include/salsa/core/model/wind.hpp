#pragma once
// Wind: the air moves, and a drone's max speed and power draw are relative to it. A test's
// "wind" is the sum of a constant velocity, gusts (an Ornstein–Uhlenbeck process per axis, the same
// everywhere on the map, drawn from the test's seed) and a field from a `wind` plugin (salsa/wind.hpp).
// Its numbers are declared once, here (wind_schema): the test reader and writer, timed changes and
// sweeps (wind.<name>) and the docs follow it. No "wind": off, and every output as without it.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/model/schema.hpp"
#include "salsa/parameters.hpp"
#include "salsa/rng.hpp"
#include "salsa/vec2.hpp"

namespace salsa {

/// A test's wind, without its field (the plugin is SimulationSetup::wind_field / TestSpec::wind_field).
struct Wind {
  Vec2 velocity;               ///< m/s, constant over map and time
  double gust_strength = 0;    ///< m/s: the gusts' stationary standard deviation per axis; 0: no gusts
  double gust_time_scale = 10; ///< s: their autocorrelation time (correlation e^(−lag/time_scale))
  bool operator==(const Wind&) const = default;
};

/// One number of Wind (schema.hpp), named as under "wind" with a dot for nesting: "velocity.x",
/// "velocity.y", "gusts.strength", "gusts.time_scale".
using WindProperty = Field<Wind>;
const Schema<Wind>& wind_schema();

/// Gusts are clamped to this many standard deviations (vector length): the strongest wind a test can
/// make is known before it runs (check_wind). Reached with probability e^(−8) ≈ 3·10^-4 per sample.
inline constexpr double gust_clamp = 4;

/// The largest wind speed (m/s) a drone of `drone` can be carried by at time step `dt` without
/// crossing a wall: a step at max_speed through the air plus the wind must stay within
/// min(radius, 2 m) (check_drone's rule). May be negative only when check_drone fails.
double wind_limit(const DroneConfig& drone, double dt);

/// The Ornstein–Uhlenbeck gusts, one process per axis: stationary from the start (a first draw from
/// N(0, strength²)), then the exact update v' = v·e^(−dt/τ) + σ·sqrt(1 − e^(−2dt/τ))·N(0, 1) per
/// step, x before y; clamped to gust_clamp × strength. Drawn from its own stream of the test's seed.
class Gusts {
 public:
  Gusts() = default;
  Gusts(std::uint64_t seed, double strength);
  void advance(double strength, double time_scale, double dt);
  Vec2 value() const { return value_; }

 private:
  Rng rng_;
  Vec2 value_;
};

}  // namespace salsa
