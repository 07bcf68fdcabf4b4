// A frame of a recorded run as a Snapshot.
#include "recorded_frame.hpp"

#include <cmath>
#include <limits>

namespace salsa::gui {

std::shared_ptr<const Scene> scene_of(const Recording& recording) {
  auto s = std::make_shared<Scene>();
  s->map = recording.map;
  for (const RecordedGroup& g : recording.groups) s->bases.push_back(g.base);
  s->targets = recording.targets;
  s->target_radius = recording.target_radius;
  return s;
}

Snapshot recorded_snapshot(const Recording& r, std::shared_ptr<const Scene> scene, std::size_t frame, std::size_t trail_length) {
  Snapshot snap;
  const double t = r.times.at(frame);
  snap.time = t;
  snap.dt = r.dt;
  snap.step = r.dt > 0 ? static_cast<std::uint64_t>(std::llround(t / r.dt)) : frame;
  snap.scene = std::move(scene);
  snap.test_name = r.test_name;
  for (const RecordedGroup& g : r.groups) {
    DroneConfig drone;
    drone.radius = g.radius;
    drone.camera_range = g.camera_range;
    drone.detection_range = g.detection_range;
    drone.obstacle_range = g.obstacle_range;
    snap.groups.push_back({g.name, drone});
  }
  const std::size_t n = r.drones;
  const RecordedColumn* velocity = r.column("velocity");
  const RecordedColumn* group = r.column("group");
  const RecordedColumn* camera = r.column("camera_works");
  snap.positions.resize(n);
  snap.velocities.resize(n);
  snap.drone_groups.resize(n);
  snap.status.resize(n);
  snap.camera.assign(n, 1);
  for (std::size_t id = 0; id < n; ++id) {
    snap.positions[id] = r.position(frame, id);
    if (velocity) snap.velocities[id] = {r.at(*velocity, frame, id, 0), r.at(*velocity, frame, id, 1)};
    const double g = group ? r.at(*group, frame, id) : 0;
    snap.drone_groups[id] = std::isnan(g) ? 0 : static_cast<std::uint32_t>(g);
    snap.status[id] = static_cast<DroneStatus>(r.status(frame, id));
    if (camera && r.at(*camera, frame, id) == 0) snap.camera[id] = 0;
  }
  snap.found.resize(r.targets.size());
  for (std::size_t i = 0; i < r.targets.size(); ++i) snap.found[i] = r.found_time[i] <= t ? 1 : 0;
  snap.targets_found = r.found_by_time(t);
  snap.found_version = snap.targets_found;  // found only grows with time: the count names the flags
  if (trail_length > 0) {
    constexpr double none = std::numeric_limits<double>::quiet_NaN();
    auto trails = std::make_shared<std::vector<Vec2>>(n * trail_length, Vec2{none, none});
    const std::size_t first = frame + 1 >= trail_length ? frame + 1 - trail_length : 0;
    for (std::size_t f = first; f <= frame; ++f) {
      const std::size_t slot = trail_length - 1 - (frame - f);  // oldest first, the newest last
      for (std::size_t id = 0; id < n; ++id) (*trails)[id * trail_length + slot] = r.position(f, id);
    }
    snap.trails = std::move(trails);
    snap.trail_length = trail_length;
  }
  return snap;
}

}  // namespace salsa::gui
