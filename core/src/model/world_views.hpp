#pragma once
// Worlds a plugin may be shown that are not the running simulation's: the map alone, a state built
// aside by a live change, or the simulation at an event's time.
#include <span>
#include <vector>

#include "salsa/core/model/static_geometry.hpp"
#include "salsa/world.hpp"

namespace salsa::detail {

/// A world that is not (yet) the simulation's: the map alone when targets are placed at the start (no
/// drones), or the state a live change builds aside, shown to the contact handlers before it is
/// swapped in.
class StateView final : public WorldView {
 public:
  StateView(const MapData& map, const StaticGeometry& geometry, const DroneProperties& drone, double time, double dt,
            std::span<const Vec2> positions = {}, std::span<const Vec2> velocities = {},
            std::span<const std::uint32_t> groups = {}, std::span<const DroneStatus> status = {})
      : map_(map), geometry_(geometry), drone_(drone), time_(time), dt_(dt), positions_(positions), velocities_(velocities),
        groups_(groups.begin(), groups.end()), status_(status.begin(), status.end()) {
    groups_.resize(positions.size(), 0);
    status_.resize(positions.size(), DroneStatus::flying);
  }
  Rect bounds() const override { return map_.bounds; }
  double time() const override { return time_; }
  double dt() const override { return dt_; }
  std::span<const Vec2> drone_positions() const override { return positions_; }
  std::span<const Vec2> drone_velocities() const override { return velocities_; }
  bool is_free(Vec2 p, double clearance) const override { return geometry_.is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return geometry_.ray_cast(from, to); }
  const DroneProperties& drone(std::uint32_t) const override { return drone_; }
  std::span<const std::uint32_t> drone_groups() const override { return groups_; }
  std::span<const DroneStatus> drone_status() const override { return status_; }
  std::size_t group_count() const override { return 1; }
  Vec2 base(std::uint32_t) const override { return map_.spawn; }
  const MapData& map() const override { return map_; }

 private:
  const MapData& map_;
  const StaticGeometry& geometry_;
  DroneProperties drone_;
  double time_, dt_;
  std::span<const Vec2> positions_, velocities_;
  std::vector<std::uint32_t> groups_;
  std::vector<DroneStatus> status_;
};

/// The simulation as a contact handler sees it during an event: as it is, at the event's time (a
/// sighting's time is the end of the step it was seen in, one dt after the snapshot it was seen on).
class EventView final : public WorldView {
 public:
  EventView(const WorldView& world, double time) : world_(world), time_(time) {}
  Rect bounds() const override { return world_.bounds(); }
  double time() const override { return time_; }
  double dt() const override { return world_.dt(); }
  std::span<const Vec2> drone_positions() const override { return world_.drone_positions(); }
  std::span<const Vec2> drone_velocities() const override { return world_.drone_velocities(); }
  bool is_free(Vec2 p, double clearance) const override { return world_.is_free(p, clearance); }
  std::optional<ObstacleHit> ray_cast(Vec2 from, Vec2 to) const override { return world_.ray_cast(from, to); }
  const DroneProperties& drone(std::uint32_t group) const override { return world_.drone(group); }
  std::span<const std::uint32_t> drone_groups() const override { return world_.drone_groups(); }
  std::span<const DroneStatus> drone_status() const override { return world_.drone_status(); }
  std::size_t group_count() const override { return world_.group_count(); }
  Vec2 base(std::uint32_t group) const override { return world_.base(group); }
  const MapData& map() const override { return world_.map(); }

 private:
  const WorldView& world_;
  double time_;
};

}  // namespace salsa::detail
