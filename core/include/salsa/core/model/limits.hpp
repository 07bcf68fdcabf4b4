#pragma once
// Limits: what the core can simulate faithfully, whatever made the map or the drones (a JSON file, a
// plugin, the desktop). Each check returns the field at fault and why (value and what is allowed).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "salsa/core/model/drone_config.hpp"
#include "salsa/core/model/static_geometry.hpp"
#include "salsa/core/model/wind.hpp"
#include "salsa/map.hpp"
#include "salsa/target.hpp"

namespace salsa {

/// What moves the drones: Box2D (the default), or salsa's own light physics for very large swarms
/// (walls swept, never crossed; drones pushed apart by position; parallel; docs/architecture.md).
enum class PhysicsMode { box2d, light };

struct Problem {
  std::string field;  ///< e.g. "drone.max_speed", "obstacles[2][0]"; empty: no problem
  std::string what;   ///< the value and what is allowed
  explicit operator bool() const { return !field.empty(); }
  std::string text() const { return field + ": " + what; }
};

/// Box2D 2.4 moves a body at most this far per step (b2_maxTranslation), m.
inline constexpr double box2d_max_step = 2.0;
/// Finite, positive where it must be, and a step (max_speed × dt) short enough that a drone can never
/// pass through a wall: at most its radius (contacts are discrete, continuous collision is off) and at
/// most box2d_max_step.
Problem check_drone(const DroneConfig& drone, double dt);
/// The strongest wind the test can make without its field, |velocity| + gust_clamp × gusts.strength,
/// at most wind_limit(drone, dt): what a drone at max speed can be carried by without crossing a wall
/// in one step. Field "wind.velocity" or "wind.gusts.strength".
Problem check_wind(const Wind& wind, const DroneConfig& drone, double dt);
/// Finite, ordered bounds; polygons of ≥ 3 points and lines of ≥ 2, every point finite and inside the
/// bounds; a finite spawn point.
Problem check_map(const MapData& map);
/// Box2D keeps positions in single-precision floats (the light physics in doubles): at the map's largest
/// coordinate they must still resolve 2 % of a drone's step (rounding then changes a step by at most
/// 1 %), else drones move in jumps or freeze. Field "bounds".
Problem check_resolution(const Rect& bounds, const DroneConfig& drone, double dt, PhysicsMode physics = PhysicsMode::box2d);
struct GroupSetup;
/// Room for the drones, so that they do not start (and stay) piled, every drone touching the others,
/// with time and memory growing with the square of their count: their bodies' area (Σ π radius²) at most
/// what the map's bounds hold at the densest packing of discs (π/√12 of the area), and, for the groups
/// that spawn in discs around one point, at most what the largest of their discs holds (widened by a
/// drone radius: a disc holds the centres; the default disc, drones × radius, holds its own group).
/// Field "drones" (the map) or "spawn.radius" (a pile at a spawn point); `groups` as make_setup names them.
Problem check_room(const Rect& bounds, Vec2 map_spawn, std::span<const GroupSetup> groups);
/// The densest packing of equal discs in the plane, the share of the area they cover: π/√12.
inline constexpr double disc_packing = 0.9068996821171089;

/// A target kind's radius (finite, ≥ 0) and the positions it placed (as many as asked, finite, inside
/// the bounds).
Problem check_targets(std::span<const Vec2> positions, std::size_t count, double radius, const Rect& bounds);

/// The kind's view_range for the drone's camera (m), checked finite and >= 0: how far the detect phase
/// looks for targets (TargetKind::view_range). Field "view_range".
Problem check_view_range(const TargetKind& kind, const DroneConfig& drone);

/// For a kind that moves its targets (TargetKind::moves): max_speed() finite and >= 0 (field
/// "max_speed"), and a step of `dt` s short enough that no target moves more than its radius (field
/// "dt"), so that one that ends a step clear of obstacles cannot have stepped through a wall. Nothing for
/// a static kind.
Problem check_target_motion(const TargetKind& kind, double dt);

/// Where a Simulation puts `count` targets of `kind` on `map` at the start: on the map alone, before
/// any drone is spawned (the kind's WorldView has the drone properties but no drones), with the
/// targets' own Rng stream of `seed`. Throws what the plugin throws, or std::invalid_argument with
/// check_targets', check_view_range's or check_target_motion's problem.
std::vector<Vec2> initial_targets(const TargetKind& kind, std::size_t count, const MapData& map,
                                  const StaticGeometry& geometry, const DroneConfig& drone, double dt,
                                  std::uint64_t seed);

/// What plugins see of a drone configuration (WorldView::drone()).
DroneProperties drone_properties(const DroneConfig& config);

}  // namespace salsa
