#include "salsa/core/model/wind.hpp"

#include <algorithm>
#include <cmath>

#include "salsa/core/model/simulation.hpp"  // box2d_max_step
#include "model/streams.hpp"

namespace salsa {

const Schema<Wind>& wind_schema() {
  // The ranges are what a test file may hold; check_wind adds the physics' limit (what a drone can be
  // carried by in one step) on top.
  static const Schema<Wind> schema{
      {{"velocity.x", 0, -1e3, 1e3, "m/s", "constant wind, x component (east)", 0.1},
       [](const Wind& w) { return w.velocity.x; }, [](Wind& w, double v) { w.velocity.x = v; }},
      {{"velocity.y", 0, -1e3, 1e3, "m/s", "constant wind, y component (north)", 0.1},
       [](const Wind& w) { return w.velocity.y; }, [](Wind& w, double v) { w.velocity.y = v; }},
      field<&Wind::gust_strength>({"gusts.strength", 0, 0, 1e3, "m/s", "gusts' standard deviation per axis (Ornstein-Uhlenbeck, stationary); 0: none", 0.1}),
      field<&Wind::gust_time_scale>({"gusts.time_scale", 10, 1e-3, 1e6, "s", "gusts' autocorrelation time: correlation e^(-lag/time_scale)", 0.1}),
  };
  return schema;
}

double wind_limit(const DroneConfig& d, double dt) { return std::min(d.radius, box2d_max_step) / dt - d.max_speed; }

namespace {
Vec2 clamped(Vec2 v, double strength) { return v.clamped(gust_clamp * strength); }
}  // namespace

Gusts::Gusts(std::uint64_t seed, double strength) : rng_(seed, detail::gust_stream) {
  if (strength <= 0) return;
  const double x = rng_.normal();  // x first, in its own statement: the order is not the compiler's
  value_ = clamped({strength * x, strength * rng_.normal()}, strength);
}

void Gusts::advance(double strength, double time_scale, double dt) {
  if (strength <= 0) return void(value_ = {});
  const double decay = std::exp(-dt / time_scale);
  const double spread = strength * std::sqrt(-std::expm1(-2 * dt / time_scale));  // sqrt(1 − e^(−2dt/τ)), exact for dt ≪ τ
  const double x = rng_.normal();
  value_ = clamped({decay * value_.x + spread * x, decay * value_.y + spread * rng_.normal()}, strength);
}

}  // namespace salsa
