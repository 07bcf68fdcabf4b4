// A frame of a recorded run as a Snapshot.
#include "recorded_frame.hpp"

#include <cmath>
#include <algorithm>
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
  snap.wind = recorded_wind(r, frame);
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

Inspection recorded_inspection(const Recording& r, std::size_t frame, std::uint32_t id) {
  Inspection in;
  in.id = id;
  in.recorded = true;
  in.position = r.position(frame, id);
  const RecordedColumn* group = r.column("group");
  const double g = group ? r.at(*group, frame, id) : 0;
  const std::size_t gi = std::isnan(g) ? 0 : static_cast<std::size_t>(g);
  if (gi < r.groups.size()) in.group = r.groups[gi].name;
  for (const RecordedColumn& c : r.columns) {
    StateLine line{c.model, c.name, c.unit, {}, c.type != StateColumn::Type::f64};
    for (std::size_t k = 0; k < c.width; ++k) line.values.push_back(r.at(c, frame, id, k));
    in.state.push_back(std::move(line));
  }
  const std::uint8_t status = r.status(frame, id);
  if (const RecordedColumn* camera = r.column("camera_works")) {  // the fleet's columns were recorded
    in.fleet = true;
    static const char* const names[] = {"flying", "landed", "failed", "removed"};
    in.status = status == 0 && r.at(*camera, frame, id) == 0 ? "camera_failed" : names[std::min<std::uint8_t>(status, 3)];
  }
  if (status == 0 && gi < r.groups.size()) {  // one drone against all: cheap, and only for the selection
    const double range = r.groups[gi].detection_range;
    for (std::uint32_t j = 0; j < r.drones; ++j)
      if (j != id && r.status(frame, j) == 0 && distance_squared(r.position(frame, j), in.position) <= range * range) in.neighbours.push_back(j);
  }
  return in;
}

std::vector<std::pair<Vec2, Vec2>> recorded_wind(const Recording& r, std::size_t frame) {
  const RecordedColumn* wind = r.column("wind");
  if (!wind || wind->width != 2) return {};
  // The live view's grid over the map (draw_wind scales arrows by its spacing), each cell the mean of
  // the wind its flying drones flew in; a cell without one has no arrow (zero).
  constexpr int n = Snapshot::wind_grid;
  const Rect b = r.map.bounds;
  std::vector<std::pair<Vec2, Vec2>> out;
  std::vector<int> count(n * n, 0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) out.emplace_back(Vec2{b.min.x + (x + 0.5) * b.width() / n, b.min.y + (y + 0.5) * b.height() / n}, Vec2{});
  for (std::size_t id = 0; id < r.drones; ++id) {
    if (r.status(frame, id) != 0) continue;
    const Vec2 p = r.position(frame, id), w{r.at(*wind, frame, id, 0), r.at(*wind, frame, id, 1)};
    if (!std::isfinite(w.x) || !std::isfinite(w.y)) continue;
    const int x = std::clamp(static_cast<int>((p.x - b.min.x) / b.width() * n), 0, n - 1);
    const int y = std::clamp(static_cast<int>((p.y - b.min.y) / b.height() * n), 0, n - 1);
    out[static_cast<std::size_t>(y * n + x)].second += w;
    ++count[static_cast<std::size_t>(y * n + x)];
  }
  for (std::size_t i = 0; i < out.size(); ++i)
    if (count[i] > 1) out[i].second = out[i].second * (1.0 / count[i]);
  return out;
}

}  // namespace salsa::gui
