// What any Simulation shows in a frame: its scene and the drones' state, copied into a Snapshot.
#include "snapshot.hpp"

#include <algorithm>

namespace salsa::gui {

const DroneConfig& Snapshot::drone_of(std::uint32_t id) const {
  static const DroneConfig none;
  const std::uint32_t g = group_of(id);
  return g < groups.size() ? groups[g].drone : none;
}

const StateLine* Inspection::line(std::string_view name) const {
  for (const StateLine& l : state)
    if (l.name == name) return &l;
  return nullptr;
}

std::shared_ptr<const Scene> scene_of(const Simulation& sim) {
  auto s = std::make_shared<Scene>();
  s->map = sim.map();
  for (std::uint32_t g = 0; g < sim.group_count(); ++g) s->bases.push_back(sim.base(g));
  for (const auto& t : sim.targets()) s->targets.push_back(t.position);
  s->target_radius = sim.setup().target_kind ? sim.setup().target_kind->radius() : 0;
  return s;
}

std::vector<std::uint8_t> found_flags(const Simulation& sim) {
  const auto& targets = sim.targets();
  std::vector<std::uint8_t> found(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) found[i] = targets[i].found() ? 1 : 0;
  return found;
}

void fill_snapshot(Snapshot& snap, const Simulation& sim, bool wind) {
  snap.step = sim.step_count();
  snap.time = sim.time();
  snap.dt = sim.dt();
  for (std::uint32_t g = 0; g < sim.group_count(); ++g) snap.groups.push_back({sim.setup().groups[g].name, sim.drone_config(g)});
  const auto p = sim.drone_positions(), v = sim.drone_velocities();
  snap.positions.assign(p.begin(), p.end());
  snap.velocities.assign(v.begin(), v.end());
  const auto groups = sim.drone_groups();
  const auto status = sim.drone_status();
  snap.drone_groups.assign(groups.begin(), groups.end());
  snap.status.assign(status.begin(), status.end());
  snap.camera.resize(p.size());
  for (std::uint32_t id = 0; id < p.size(); ++id) snap.camera[id] = sim.camera_works(id) ? 1 : 0;
  if (sim.targets_move())
    for (const TargetState& t : sim.targets()) snap.targets.push_back(t.position);
  if (wind) {
    const Rect b = sim.bounds();
    const double t = sim.time();
    try {  // a field plugin: its failure stops the run at the next step, which says why
      for (int y = 0; y < Snapshot::wind_grid; ++y)
        for (int x = 0; x < Snapshot::wind_grid; ++x) {
          const Vec2 at{b.min.x + (x + 0.5) * b.width() / Snapshot::wind_grid, b.min.y + (y + 0.5) * b.height() / Snapshot::wind_grid};
          snap.wind.emplace_back(at, sim.wind_at(at, t));
        }
    } catch (const std::exception&) {
      snap.wind.clear();
    }
  }
  if (sim.setup().comm.on)
    for (std::uint32_t id = 0; id < p.size() && snap.links.size() < Snapshot::max_links; ++id)
      for (const Message& m : sim.inbox(id)) snap.links.emplace_back(id, m.sender);
  std::sort(snap.links.begin(), snap.links.end());  // inboxes come in grid order; the view looks pairs up
}

}  // namespace salsa::gui
